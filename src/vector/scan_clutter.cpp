#include "glassmap/vector/scan_clutter.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <queue>
#include <span>
#include <vector>

#include <Eigen/Eigenvalues>

#include "glassmap/core/angles.hpp"
#include "segment_index.hpp"

namespace glassmap::vector {
namespace {

using Vec2f = Eigen::Vector2f;

// The returns no wall or pane explains, relative to an origin (float: a map frame is local),
// merged into weighted points of 2 cm (a surface seen from many scans is hit at the same places
// again and again), in square cells for the line walks.
class Returns {
 public:
  Returns(std::vector<Vec2f> raw, double cell) {
    constexpr float kMerge = 0.02f;
    // Each return's 2 cm square (row, column), sorted once with the return's index: the same
    // order, and so the same sums, whatever the sort does with equal keys.
    struct Keyed {
      std::int64_t row, col;
      std::uint32_t index;
      bool operator<(const Keyed& k) const {
        return row != k.row ? row < k.row : (col != k.col ? col < k.col : index < k.index);
      }
    };
    std::vector<Keyed> keyed(raw.size());
    tbb::parallel_for(std::size_t{0}, raw.size(), [&](std::size_t i) {
      keyed[i] = {static_cast<std::int64_t>(std::floor(raw[i].y() / kMerge)),
                  static_cast<std::int64_t>(std::floor(raw[i].x() / kMerge)), static_cast<std::uint32_t>(i)};
    });
    // The keys are distinct (the index breaks ties): any sort, on any number of threads, gives
    // this one order.
    tbb::parallel_sort(keyed.begin(), keyed.end());
    for (std::size_t i = 0; i < keyed.size();) {
      std::size_t j = i;
      Eigen::Vector2d sum = Eigen::Vector2d::Zero();
      while (j < keyed.size() && keyed[j].row == keyed[i].row && keyed[j].col == keyed[i].col)
        sum += raw[keyed[j++].index].cast<double>();
      points_.push_back((sum / static_cast<double>(j - i)).cast<float>());
      weight_.push_back(static_cast<std::uint32_t>(j - i));
      i = j;
    }
    alive_.assign(points_.size(), 1);
    Eigen::AlignedBox2f box;
    for (const Vec2f& p : points_) box.extend(p);
    if (box.isEmpty()) return;
    lo_ = box.min();
    const Eigen::Vector2d size = (box.max() - box.min()).cast<double>();
    // Coarser cells on huge extents (a stray return far away) so the cells stay few.
    cell_ = std::max(cell, std::sqrt((size.x() + cell) * (size.y() + cell) / 1e6));
    nx_ = static_cast<std::size_t>(size.x() / cell_) + 1;
    ny_ = static_cast<std::size_t>(size.y() / cell_) + 1;
    start_.assign(nx_ * ny_ + 1, 0);
    std::vector<std::uint32_t> cell_of(points_.size());
    for (std::size_t i = 0; i < points_.size(); ++i) {
      cell_of[i] = static_cast<std::uint32_t>(cellIndex(points_[i]));
      ++start_[cell_of[i] + 1];
    }
    for (std::size_t c = 0; c < nx_ * ny_; ++c) start_[c + 1] += start_[c];
    members_.resize(points_.size());
    std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
    for (std::size_t i = 0; i < points_.size(); ++i) members_[fill[cell_of[i]]++] = static_cast<std::uint32_t>(i);
  }

  std::size_t cells() const { return nx_ * ny_; }
  std::size_t size() const { return points_.size(); }
  double cell() const { return cell_; }
  const Vec2f& point(std::uint32_t i) const { return points_[i]; }
  std::uint32_t weight(std::uint32_t i) const { return weight_[i]; }
  bool alive(std::uint32_t i) const { return alive_[i] != 0; }
  void take(std::uint32_t i) { alive_[i] = 0; }
  std::span<const std::uint32_t> members(std::size_t c) const {
    return {members_.data() + start_[c], members_.data() + start_[c + 1]};
  }
  // The cell holding p, or cells() outside.
  std::size_t cellAt(const Eigen::Vector2d& p) const {
    const Eigen::Vector2d q = (p - lo_.cast<double>()) / cell_;
    if (!(q.x() >= 0 && q.y() >= 0 && q.x() < static_cast<double>(nx_) && q.y() < static_cast<double>(ny_)))
      return cells();
    return static_cast<std::size_t>(q.y()) * nx_ + static_cast<std::size_t>(q.x());
  }

 private:
  std::size_t cellIndex(const Vec2f& p) const {
    const std::size_t x = std::min(static_cast<std::size_t>((p.x() - lo_.x()) / cell_), nx_ - 1);
    const std::size_t y = std::min(static_cast<std::size_t>((p.y() - lo_.y()) / cell_), ny_ - 1);
    return y * nx_ + x;
  }
  std::vector<Vec2f> points_;
  std::vector<std::uint32_t> weight_;
  std::vector<std::uint8_t> alive_;
  Vec2f lo_ = Vec2f::Zero();
  double cell_ = 0.25;
  std::size_t nx_ = 0, ny_ = 0;
  std::vector<std::uint32_t> start_, members_;
};

// A line through the returns: its live returns within the tolerance, contiguous along it.
struct Line {
  std::size_t count = 0;  // returns (the weights of its points)
  Eigen::Vector2d a = Eigen::Vector2d::Zero(), b = Eigen::Vector2d::Zero();
  std::vector<std::uint32_t> inliers;
};

struct Scratch {
  std::vector<std::size_t> cells;
  std::vector<std::pair<double, std::uint32_t>> along;  // (position along the line, return)
  // For runCount: per bucket along the line the least and greatest position, and per return the
  // last count that took it (a return may be collected twice).
  std::vector<double> bucket_lo, bucket_hi;
  std::vector<std::uint32_t> taken;
  std::uint32_t stamp = 0;
};

// The map's labels, the map frame in the grid's, and where the returns' origin lies in the map.
struct FreeSpace {
  const LabelGrid* grid = nullptr;
  Pose2 to_grid;
  Eigen::Vector2d shift = Eigen::Vector2d::Zero();
  Eigen::Matrix2d rotation = to_grid.rotation();  // to_grid's, made once: the walks ask millions of cells

  // The cell (x, y) holding p (relative to the returns' origin), false outside the grid.
  bool cellOf(const Eigen::Vector2d& p, int& x, int& y) const {
    const Eigen::Vector2d q = (to_grid.t + rotation * Vec2(shift + p) - grid->origin) / grid->resolution;
    if (!(q.x() >= 0 && q.y() >= 0 && q.x() < grid->width && q.y() < grid->height)) return false;
    x = static_cast<int>(q.x()), y = static_cast<int>(q.y());
    return true;
  }
  bool empty(int x, int y) const {
    return x >= 0 && y >= 0 && x < grid->width && y < grid->height && grid->code(x, y) == kCodeEmpty;
  }
  // Whether the line point p lies in a cell seen empty.
  bool at(const Eigen::Vector2d& p) const {
    int x = 0, y = 0;
    return cellOf(p, x, y) && empty(x, y);
  }
  // Whether the return p lies in free space: its cell and the eight around it seen empty. A return
  // there was something the beams passed later (a person walking, a door moved), not a surface.
  bool around(const Eigen::Vector2d& p) const {
    int x = 0, y = 0;
    if (!grid || !cellOf(p, x, y)) return false;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx)
        if (!empty(x + dx, y + dy)) return false;
    return true;
  }
};

// walkLine's walk: the live returns within the tolerance into s.along (a return may come twice),
// and how far the line may run back (limit[0]) and forth (limit[1]) from c.
void collectAlong(const Returns& r, const Eigen::Vector2d& c, const Eigen::Vector2d& d, const ScanClutterOptions& o,
                  const FreeSpace& free_space, Scratch& s, double max_length, double limit[2]) {
  const Eigen::Vector2d n(-d.y(), d.x());
  const double cell_step = 0.5 * r.cell(), diag = r.cell() * std::sqrt(2.0);
  const double free_step = free_space.grid ? std::min(cell_step, 0.5 * free_space.grid->resolution) : cell_step;
  s.along.clear();
  limit[0] = limit[1] = max_length;
  for (const double sign : {-1.0, 1.0}) {
    double& end = limit[sign > 0 ? 1 : 0];
    s.cells.clear();
    double reach = 0.0, next_cell = 0.0, free_from = -1.0;
    for (double t = 0.0; t <= end; t += free_step) {
      if (free_space.grid) {
        if (!free_space.at(c + sign * t * d)) {
          free_from = -1.0;
        } else if (free_from < 0.0) {
          free_from = t;
        } else if (t - free_from > o.max_free) {
          end = free_from;
          break;
        }
      }
      if (t < next_cell) continue;
      next_cell += cell_step;
      const std::size_t before = s.along.size();
      if (s.cells.size() > 64) s.cells.erase(s.cells.begin(), s.cells.end() - 16);  // only recent cells can repeat
      for (double across : {-o.tolerance, 0.0, o.tolerance}) {
        const std::size_t cell = r.cellAt(c + sign * t * d + across * n);
        if (cell >= r.cells() || std::find(s.cells.begin(), s.cells.end(), cell) != s.cells.end()) continue;
        s.cells.push_back(cell);
        for (std::uint32_t i : r.members(cell)) {
          if (!r.alive(i)) continue;
          const Eigen::Vector2d q = r.point(i).cast<double>() - c;
          if (std::abs(q.dot(n)) < o.tolerance) s.along.emplace_back(q.dot(d), i);
        }
      }
      // Every return within `diag` behind the walk has been seen: stop a gap beyond the farthest.
      for (std::size_t k = before; k < s.along.size(); ++k) reach = std::max(reach, sign * s.along[k].first);
      if (t - diag > reach + o.max_gap) {
        end = std::min(end, t);
        break;
      }
    }
  }
}

// The live returns within o.tolerance of the line through c along d, the contiguous run that
// holds the return nearest to c: no gap over o.max_gap between its returns, and the line does
// not cross free space (cells seen empty) for more than o.max_free, since a surface lies where
// the beams ended, not where they passed. Walked outward from c, the returns' cells every half
// cell, the labels every half grid cell.
Line walkLine(const Returns& r, const Eigen::Vector2d& c, const Eigen::Vector2d& d, const ScanClutterOptions& o,
              const FreeSpace& free_space, Scratch& s, double max_length) {
  double limit[2];
  collectAlong(r, c, d, o, free_space, s, max_length, limit);
  Line out;
  std::sort(s.along.begin(), s.along.end());
  s.along.erase(std::unique(s.along.begin(), s.along.end()), s.along.end());
  const auto first = std::lower_bound(s.along.begin(), s.along.end(), std::make_pair(-limit[0], std::uint32_t{0}));
  const auto last = std::upper_bound(s.along.begin(), s.along.end(),
                                     std::make_pair(limit[1], std::numeric_limits<std::uint32_t>::max()));
  if (first >= last) return out;
  // The run holding the return nearest to c.
  auto near = first;
  for (auto k = first; k != last; ++k)
    if (std::abs(k->first) < std::abs(near->first)) near = k;
  auto lo = near, hi = near;
  while (lo != first && lo->first - (lo - 1)->first <= o.max_gap) --lo;
  while (hi + 1 != last && (hi + 1)->first - hi->first <= o.max_gap) ++hi;
  out.a = c + lo->first * d;
  out.b = c + hi->first * d;
  out.inliers.reserve(static_cast<std::size_t>(hi - lo) + 1);
  for (auto k = lo; k <= hi; ++k) {
    out.inliers.push_back(k->second);
    out.count += r.weight(k->second);
  }
  return out;
}

// The count of the line through c along d (what walkLine's Line::count would be) without sorting
// the returns: the runs are told apart by the least and greatest position in buckets of half the
// longest gap along the line (no gap within a bucket can break a run), so the run holding the
// return nearest to c joins the next non-empty bucket exactly when walkLine's sorted neighbours
// would. fitAtSeed asks it of every orientation; only the best few are walked in full.
std::size_t runCount(const Returns& r, const Eigen::Vector2d& c, const Eigen::Vector2d& d, const ScanClutterOptions& o,
                     const FreeSpace& free_space, Scratch& s, double max_length) {
  if (!(o.max_gap > 0.0)) return walkLine(r, c, d, o, free_space, s, max_length).count;
  double limit[2];
  collectAlong(r, c, d, o, free_space, s, max_length, limit);
  const double width = 0.5 * o.max_gap;
  const std::size_t buckets = static_cast<std::size_t>(std::ceil((limit[0] + limit[1]) / width)) + 1;
  s.bucket_lo.assign(buckets, std::numeric_limits<double>::infinity());
  s.bucket_hi.assign(buckets, -std::numeric_limits<double>::infinity());
  // The return nearest to c, as walkLine's scan of the sorted returns finds it: the least |t|,
  // then the least t, then the least index.
  const std::pair<double, std::uint32_t>* near = nullptr;
  const auto bucketOf = [&](double t) {
    return std::min(buckets - 1, static_cast<std::size_t>((t + limit[0]) / width));
  };
  for (const auto& e : s.along) {
    if (e.first < -limit[0] || e.first > limit[1]) continue;
    const std::size_t b = bucketOf(e.first);
    s.bucket_lo[b] = std::min(s.bucket_lo[b], e.first);
    s.bucket_hi[b] = std::max(s.bucket_hi[b], e.first);
    if (!near || std::abs(e.first) < std::abs(near->first) || (std::abs(e.first) == std::abs(near->first) && e < *near))
      near = &e;
  }
  if (!near) return 0;
  const std::size_t home = bucketOf(near->first);
  double lo = s.bucket_lo[home], hi = s.bucket_hi[home];
  for (std::size_t b = home; b-- > 0;) {
    if (s.bucket_hi[b] < s.bucket_lo[b]) continue;  // empty
    if (lo - s.bucket_hi[b] > o.max_gap) break;
    lo = s.bucket_lo[b];
  }
  for (std::size_t b = home + 1; b < buckets; ++b) {
    if (s.bucket_hi[b] < s.bucket_lo[b]) continue;
    if (s.bucket_lo[b] - hi > o.max_gap) break;
    hi = s.bucket_hi[b];
  }
  if (s.taken.size() != r.size()) s.taken.assign(r.size(), 0);
  if (++s.stamp == 0) {  // the stamps wrapped: start again
    std::fill(s.taken.begin(), s.taken.end(), 0);
    s.stamp = 1;
  }
  std::size_t count = 0;
  for (const auto& [t, i] : s.along)
    if (t >= lo && t <= hi && s.taken[i] != s.stamp) {
      s.taken[i] = s.stamp;
      count += r.weight(i);
    }
  return count;
}

// Mean offset across the line of a run's returns, and their principal axis.
void runShape(const Returns& r, const Line& line, const Eigen::Vector2d& c, const Eigen::Vector2d& d,
              Eigen::Vector2d& centroid, Eigen::Vector2d& axis, double& offset) {
  const Eigen::Vector2d n(-d.y(), d.x());
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (std::uint32_t i : line.inliers) sum += r.weight(i) * (r.point(i).cast<double>() - c);
  const double count = static_cast<double>(line.count);
  centroid = c + sum / count;
  offset = (sum / count).dot(n);
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (std::uint32_t i : line.inliers) {
    const Eigen::Vector2d q = r.point(i).cast<double>() - centroid;
    cov += r.weight(i) * q * q.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
  axis = eig.eigenvectors().col(1);
}

// How far either way the orientations are first compared [m].
constexpr double kProbe = 1.0;

// The best line at a seed cell: from the mean of its densest part, every orientation, its band
// re-centred once, then the principal axis of the best run's returns.
Line fitAtSeed(const Returns& r, std::size_t seed, const ScanClutterOptions& o, const FreeSpace& free_space,
               Scratch& s) {
  // The densest fifth-of-a-cell square of the seed cell's live returns.
  constexpr int kSub = 5;
  std::size_t count[kSub * kSub] = {};
  Eigen::Vector2d sum[kSub * kSub];
  for (auto& v : sum) v.setZero();
  Eigen::Vector2f lo(std::numeric_limits<float>::max(), std::numeric_limits<float>::max());
  for (std::uint32_t i : r.members(seed))
    if (r.alive(i)) lo = lo.cwiseMin(r.point(i));
  std::size_t live = 0;
  for (std::uint32_t i : r.members(seed)) {
    if (!r.alive(i)) continue;
    const Eigen::Vector2f q = (r.point(i) - lo) / static_cast<float>(r.cell() / kSub);
    const int k = std::min(static_cast<int>(q.y()), kSub - 1) * kSub + std::min(static_cast<int>(q.x()), kSub - 1);
    count[k] += r.weight(i);
    sum[k] += r.weight(i) * r.point(i).cast<double>();
    live += r.weight(i);
  }
  Line best;
  if (live < 3) return best;
  const int densest = static_cast<int>(std::max_element(count, count + kSub * kSub) - count);
  const Eigen::Vector2d c0 = sum[densest] / static_cast<double>(count[densest]);
  // Every orientation over a short reach first (a line through a blob and a surface differ there
  // already), then the two best over the whole reach, their band re-centred once.
  const int steps = std::max(1, static_cast<int>(std::lround(180.0 / o.angle_step_deg)));
  std::pair<std::size_t, int> top[2] = {{0, -1}, {0, -1}};
  for (int k = 0; k < steps; ++k) {
    const double theta = kPi * k / steps;
    const std::size_t count =
        runCount(r, c0, Eigen::Vector2d(std::cos(theta), std::sin(theta)), o, free_space, s, kProbe);
    if (count > top[0].first) {
      top[1] = top[0];
      top[0] = {count, k};
    } else if (count > top[1].first) {
      top[1] = {count, k};
    }
  }
  for (const auto& [count, k] : top) {
    if (k < 0) continue;
    const double theta = kPi * k / steps;
    const Eigen::Vector2d d(std::cos(theta), std::sin(theta));
    Line line = walkLine(r, c0, d, o, free_space, s, o.max_length);
    if (line.count >= 3) {
      Eigen::Vector2d centroid, axis;
      double offset = 0.0;
      runShape(r, line, c0, d, centroid, axis, offset);
      Line moved = walkLine(r, c0 + offset * Eigen::Vector2d(-d.y(), d.x()), d, o, free_space, s, o.max_length);
      if (moved.count > line.count) line = std::move(moved);
    }
    if (line.count > best.count) best = std::move(line);
  }
  if (best.count >= 3) {
    const Eigen::Vector2d d =
        (best.b - best.a).norm() > 0 ? Eigen::Vector2d((best.b - best.a).normalized()) : Eigen::Vector2d(1.0, 0.0);
    Eigen::Vector2d centroid, axis;
    double offset = 0.0;
    runShape(r, best, best.a, d, centroid, axis, offset);
    Line refit = walkLine(r, centroid, axis, o, free_space, s, o.max_length);
    if (refit.count > best.count) best = std::move(refit);
  }
  return best;
}

}  // namespace

ScanClutterStats clutterFromScans(VectorizeResult& plan, const LaserLog& log, const grid::BeamOptions& beams,
                                  const LabelGrid* free_space, const Pose2& grid_pose, const ScanClutterOptions& o) {
  const Pose2 to_grid = grid_pose.inverse();
  const FreeSpace labels{free_space, to_grid, Eigen::Vector2d::Zero()};  // returns in the map frame
  const auto t0 = std::chrono::steady_clock::now();
  ScanClutterStats stats;
  if (!o.enabled || !(o.tolerance > 0) || !(o.seed_cell > 0) || !(o.angle_step_deg > 0)) return stats;

  // The returns, which of them the walls and panes explain, and which the cells' clutter pieces
  // (kept aside: the step gives some of them back if its lines explain less than they did).
  const std::vector<MapSegment> pieces = std::move(plan.extras.clutter.segments);
  plan.extras.clutter.segments.clear();
  std::vector<const MapSegment*> walls, cells;
  for (const MapSegment& s : plan.map.segments)
    if (s.length() > 0) walls.push_back(&s);
  for (const MapSegment& s : pieces)
    if (s.length() > 0) cells.push_back(&s);
  const detail::SegmentIndex wall_index(walls, o.tolerance), cell_index(cells, o.tolerance);
  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  // The cells' piece nearest to p within the tolerance (the lower index on a tie), or kNone.
  const auto nearestPiece = [&](const Vec2& p) {
    std::uint32_t which = kNone;
    double best = o.tolerance;
    if (const auto* cands = cell_index.near(p))
      for (std::uint32_t k : *cands) {
        const double d = cells[k]->distanceTo(p);
        if (d < best || (d == best && k < which)) best = d, which = k;
      }
    return which;
  };
  // Whether some wall or pane lies within the tolerance of p (the first found will do).
  const auto byWall = [&](const Vec2& p) {
    if (const auto* cands = wall_index.near(p))
      for (std::uint32_t k : *cands)
        if (walls[k]->distanceTo(p) <= o.tolerance) return true;
    return false;
  };
  bool have_origin = false;
  Vec2 origin = Vec2::Zero();
  std::vector<Vec2f> unexplained;
  std::vector<std::size_t> free_near_piece(cells.size(), 0);  // returns in free space near each piece
  std::size_t returns = 0, near_walls = 0, near_cells = 0;
  forEachScanBlock(log, [&](std::span<const LaserScan> block, std::size_t) {
    struct Kept {
      std::vector<Vec2> points;
      std::vector<std::uint32_t> free_pieces;
      std::size_t returns = 0, near_walls = 0, near_cells = 0;
    };
    std::vector<Kept> kept(block.size());
    tbb::parallel_for(std::size_t{0}, block.size(), [&](std::size_t i) {
      Kept& k = kept[i];
      grid::forEachBeam(
          block[i], beams,
          [&](const grid::Beam& beam) {
            if (!(beam.range < o.max_range)) return;
            ++k.returns;
            // To the millimetre: a log whose angles were stored as float32 (a ROS bag) then gives
            // the same returns as its double original, but where one lies on a rounding edge.
            const Vec2 p = (beam.to / 1e-3).array().round().matrix() * 1e-3;
            if (byWall(p)) {
              ++k.near_walls;
              return;
            }
            const std::uint32_t piece = nearestPiece(p);
            k.near_cells += piece != kNone ? 1 : 0;
            if (!labels.around(p))
              k.points.push_back(p);
            else if (piece != kNone)
              k.free_pieces.push_back(piece);
          },
          grid::BeamFilter::Hit);
    });
    for (const Kept& k : kept) {
      returns += k.returns;
      near_walls += k.near_walls;
      near_cells += k.near_cells;
      for (std::uint32_t piece : k.free_pieces) ++free_near_piece[piece];
      for (const Vec2& p : k.points) {
        if (!have_origin) origin = p, have_origin = true;
        unexplained.push_back((p - origin).cast<float>());
      }
    }
  });
  stats.returns = returns;
  stats.unexplained = unexplained.size();
  if (returns == 0) {
    plan.extras.clutter.segments = pieces;
    return stats;
  }
  stats.explained_before = static_cast<double>(near_walls + near_cells) / static_cast<double>(returns);
  stats.explained_walls = static_cast<double>(near_walls) / static_cast<double>(returns);

  // Every seed cell's best line, in parallel (each writes its own slot), then the lazy greedy cover.
  Returns r(std::move(unexplained), o.seed_cell);
  const FreeSpace space{free_space, to_grid, origin};
  const std::size_t need = std::max<std::size_t>(3, static_cast<std::size_t>(std::ceil(o.min_share * returns)));
  std::vector<Line> best(r.cells());
  tbb::enumerable_thread_specific<Scratch> scratch;
  tbb::parallel_for(std::size_t{0}, r.cells(), [&](std::size_t c) {
    std::size_t w = 0;
    for (std::uint32_t i : r.members(c)) w += r.weight(i);
    if (w >= 3) best[c] = fitAtSeed(r, c, o, space, scratch.local());
  });
  std::size_t candidates = r.cells();
  using Entry = std::pair<std::size_t, std::size_t>;  // (count, seed): the largest count first, then the lower seed
  auto later = [](const Entry& x, const Entry& y) {
    return x.first != y.first ? x.first < y.first : x.second > y.second;
  };
  std::priority_queue<Entry, std::vector<Entry>, decltype(later)> queue(later);
  for (std::size_t c = 0; c < r.cells(); ++c)
    if (best[c].count >= need) queue.emplace(best[c].count, c);
  std::size_t covered = 0;
  Scratch& s = scratch.local();
  while (!queue.empty()) {
    const auto [count, seed] = queue.top();
    queue.pop();
    Line& line = best[seed];
    std::size_t live = 0;
    for (std::uint32_t i : line.inliers) live += r.alive(i) ? r.weight(i) : 0;
    if (live == count && (line.b - line.a).norm() >= o.min_length) {
      for (std::uint32_t i : line.inliers) r.take(i);
      covered += count;
      MapSegment& seg = plan.extras.clutter.add(origin + line.a, origin + line.b, Material::Wall);
      seg.support = static_cast<std::uint32_t>(count);
    } else if (live == count) {
      continue;  // too short to draw: the seed gives up
    }
    // The seed may hold another line (a corner), or its line lost returns to another: refit.
    line = fitAtSeed(r, seed, o, space, s);
    ++candidates;
    if (line.count >= need) queue.emplace(line.count, seed);
  }
  stats.added = plan.extras.clutter.segments.size();
  stats.candidates = candidates;

  // The lines never explain less than the cells' pieces did: where they do (many small objects,
  // each hit by fewer than min_share of a long log's returns), the pieces whose returns no line
  // took come back, those with the most first, until the share is reached again.
  if (near_walls + covered < near_walls + near_cells) {
    std::vector<std::size_t> gain = free_near_piece;
    for (std::uint32_t i = 0; i < r.size(); ++i)
      if (r.alive(i)) {
        const std::uint32_t piece = nearestPiece(origin + r.point(i).cast<double>());
        if (piece != kNone) gain[piece] += r.weight(i);
      }
    std::vector<std::uint32_t> order(cells.size());
    for (std::uint32_t k = 0; k < order.size(); ++k) order[k] = k;
    std::sort(order.begin(), order.end(),
              [&](std::uint32_t x, std::uint32_t y) { return gain[x] != gain[y] ? gain[x] > gain[y] : x < y; });
    for (std::uint32_t k : order) {
      if (covered >= near_cells || gain[k] == 0) break;
      plan.extras.clutter.segments.push_back(*cells[k]);
      covered += gain[k];
      ++stats.restored;
    }
  }
  stats.replaced = cells.size() - stats.restored;
  stats.explained_after = static_cast<double>(near_walls + covered) / static_cast<double>(returns);
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return stats;
}

}  // namespace glassmap::vector
