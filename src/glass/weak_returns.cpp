#include "weak_returns.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "glass_tiles.hpp"
#include "glassmap/grid/distance_transform.hpp"
#include "glassmap/grid/parallel_scans.hpp"
#include "glassmap/grid/traversal.hpp"

namespace glassmap::glass::sparse {
namespace {

// Coarse tiles of 8 x 8 cells, each with the number of undecided cells in it and its eight
// neighbouring tiles: a segment whose walk over the tiles meets only zeros crosses no such cell.
// Counts only fall, and a cell's fall only once it is decided, so a walk that reads a stale count
// reads a larger one (and walks a beam it could have skipped).
class UndecidedTiles {
 public:
  explicit UndecidedTiles(const grid::GridGeometry& g)
      : coarse_(detail::coarseGrid(g, kTile)), count_(coarse_.cells()) {}
  void add(int x, int y) { update(x, y, +1); }
  void remove(int x, int y) { update(x, y, -1); }
  /// True when segment a -> b passes an undecided cell's tile; `from`: detail::firstTile's.
  bool near(const Vec2& a, const Vec2& b, double* from) const {
    return detail::firstTile(
        coarse_, coarse_.resolution / kTile, a, b,
        [&](int x, int y) { return count_[coarse_.index(x, y)].load(std::memory_order_relaxed) != 0; }, from);
  }

 private:
  static constexpr int kTile = 8;
  void update(int x, int y, int d) {
    for (int ty = y / kTile - 1; ty <= y / kTile + 1; ++ty)
      for (int tx = x / kTile - 1; tx <= x / kTile + 1; ++tx)
        if (coarse_.contains(tx, ty))
          count_[coarse_.index(tx, ty)].fetch_add(static_cast<std::uint32_t>(d), std::memory_order_relaxed);
  }
  grid::GridGeometry coarse_;
  std::vector<std::atomic<std::uint32_t>> count_;
};

// Which of `cells` (linear cell indices, ascending) are passed by most beams: at least
// o.min_through beams cross the cell (returned beams that end at least o.through_margin beyond it;
// beams without an echo within the cap, before the first occupied cell of `label` they meet), and
// the returned beams whose walk ends there (hits, per cell) are at most o.max_hit_ratio of those
// and these. A pane with nothing in range behind it (a facade over open ground) is passed by beams
// that bring no echo back; a wall's dropouts stop at the wall. The test holds for good once a
// cell's passes are enough, so a cell is decided then and the beams that cross only decided cells'
// tiles are not walked; the answer is that of counting every beam.
std::vector<std::uint8_t> passedCells(const LaserLog& log, const grid::BeamOptions& beams, const SparsePaneOptions& o,
                                      const grid::GridGeometry& g, const std::vector<std::uint8_t>& label,
                                      const std::vector<std::uint32_t>& cells, const std::vector<std::uint32_t>& hits) {
  const std::size_t n = cells.size();
  const detail::CandidateIndex slot(g, cells);
  const auto holds = [&](std::size_t k, std::uint32_t passes) {
    return !(passes < static_cast<std::uint32_t>(o.min_through) ||
             hits[k] > o.max_hit_ratio * static_cast<double>(hits[k] + passes));
  };

  std::vector<std::atomic<std::uint32_t>> passes(n);
  std::vector<std::atomic<std::uint8_t>> decided(n);
  UndecidedTiles undecided(g);
  for (std::size_t k = 0; k < n; ++k) {
    const grid::CellIndex c = g.cellOf(cells[k]);
    if (holds(k, 0))
      decided[k].store(1, std::memory_order_relaxed);
    else
      undecided.add(c.x, c.y);
  }
  tbb::enumerable_thread_specific<int> unused;
  grid::forScansInParallel(log, {}, unused, [&](const LaserScan& scan, std::size_t, int&) {
    grid::forEachBeam(scan, beams, [&](const grid::Beam& beam) {
      double from = 0.0;
      if (!undecided.near(beam.from, beam.to, &from)) return;
      auto pass = [&](int x, int y) {
        const std::int64_t found = slot.find(x, y);
        if (found < 0) return;
        const auto k = static_cast<std::size_t>(found);
        if (decided[k].load(std::memory_order_relaxed)) return;
        const std::uint32_t p = passes[k].fetch_add(1, std::memory_order_relaxed) + 1;
        if (holds(k, p) && decided[k].exchange(1, std::memory_order_relaxed) == 0) undecided.remove(x, y);
      };
      if (!beam.hit) {
        // No echo within the cap: every cell before the first occupied one (so from the start), and
        // through_margin plus 3 sigma(r) short of the beam's end (a surface at the edge of the
        // range reads beyond it as often as not: those beams did not pass it).
        const double sigma = rangeSigma(o, beam.range);
        const double until = beam.range - o.through_margin - 3.0 * sigma;
        grid::traverse(g, beam.from, beam.to, [&](int x, int y, double enter, bool) {
          if (label[g.index(x, y)] == kOccupied || !(enter * beam.range < until)) return false;
          pass(x, y);
          return true;
        });
        return;
      }
      const double pass_until = beam.range - o.through_margin;
      // From an undecided cell's tile on: the cells before it are decided or no candidates.
      grid::traverse(
          g, beam.from, beam.to,
          [&](int x, int y, double enter, bool last) {
            if (!last && enter * beam.range < pass_until) pass(x, y);
          },
          from);
    });
  });
  std::vector<std::uint8_t> out(n);
  for (std::size_t k = 0; k < n; ++k) out[k] = decided[k].load(std::memory_order_relaxed);
  return out;
}

}  // namespace

double clearUntil(const grid::GridGeometry& g, const std::vector<std::uint8_t>& label, const Vec2& a, const Vec2& b) {
  double t = 1.0;
  grid::traverse(g, a, b, [&](int x, int y, double enter, bool) {
    if (label[g.index(x, y)] != kOccupied) return true;
    t = enter;
    return false;
  });
  return t;
}

WeakReturns::WeakReturns(const LaserLog& log, const grid::BeamOptions& beams, const SparsePaneOptions& o,
                         const CellEvidence& e)
    : bins_(kAngleBins), cells_per_bin_(kAngleBins, 0.0) {
  const grid::GridGeometry& g = e.geometry;
  // Distance to the nearest occupied cell: the ends and corners of walls, seen past from most
  // directions and hit from a few, and the noise-spread front of a wall seen at grazing incidence
  // look like faint panes too.
  std::vector<std::uint8_t> wall(g.cells());
  for (std::size_t i = 0; i < wall.size(); ++i) wall[i] = e.label[i] == kOccupied;
  const std::vector<float> wall_distance = grid::distanceTransform(g.width, g.height, wall);  // [cells]
  // The returns that may be weak (in range, on a candidate, clear of the walls; the passes decide
  // after), in scan order.
  struct Candidate {
    Vec2 at, from;
    double angle;
    std::uint32_t cell;
  };
  // And every candidate's hits: the returned beams whose walk ends there (the last cell of the walk).
  const double least_clearance = std::max(o.wall_clearance, 3.0 * o.range_sigma);
  std::vector<std::vector<Candidate>> per_scan(log.scanCount());
  const detail::CandidateIndex candidate(e);
  tbb::enumerable_thread_specific<std::vector<std::uint32_t>> hit_parts(
      [&] { return std::vector<std::uint32_t>(e.cells.size(), 0); });
  grid::forScansInParallel(
      log, {}, hit_parts, [&](const LaserScan& scan, std::size_t index, std::vector<std::uint32_t>& hits) {
        // Beyond this range a beam is wider than max_footprint cells: a cell's returns and passes then
        // mix the surfaces the beam grazes.
        const double max_range = o.max_footprint * g.resolution / std::max(std::abs(scan.angular_step), 1e-6);
        std::vector<Candidate>& out = per_scan[index];
        grid::forEachBeam(scan, beams, [&](const grid::Beam& beam) {
          if (!beam.hit) return;
          grid::CellIndex end;
          if (grid::lastCell(g, beam.from, beam.to, end)) {
            const std::int64_t id = candidate.find(end.x, end.y);
            if (id >= 0) ++hits[static_cast<std::size_t>(id)];
          }
          if (beam.range < o.min_range || beam.range > max_range) return;
          const auto cell = static_cast<std::uint32_t>(g.index(g.cellAt(beam.to)));
          if (wall_distance[cell] * g.resolution <= least_clearance) return;
          if (e.candidate(cell) < 0) return;
          const double sigma = rangeSigma(o, beam.range);
          if (wall_distance[cell] * g.resolution <= std::max(o.wall_clearance, 3.0 * sigma)) return;
          out.push_back({beam.to, beam.from, beam.angle, cell});
        });
      });
  std::vector<Candidate> candidates;
  for (std::vector<Candidate>& c : per_scan) {
    candidates.insert(candidates.end(), c.begin(), c.end());
    c = {};
  }
  // Their cells' passes.
  std::vector<std::uint32_t> cells;
  for (const Candidate& r : candidates) cells.push_back(r.cell);
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  std::vector<std::uint32_t> hits(cells.size(), 0);
  for (const std::vector<std::uint32_t>& part : hit_parts)
    for (std::size_t k = 0; k < cells.size(); ++k) hits[k] += part[static_cast<std::size_t>(e.candidate(cells[k]))];
  const std::vector<std::uint8_t> passed = passedCells(log, beams, o, g, e.label, cells, hits);
  for (const Candidate& r : candidates) {
    const auto k = static_cast<std::size_t>(std::lower_bound(cells.begin(), cells.end(), r.cell) - cells.begin());
    if (passed[k]) returns_.push_back({r.at, r.from, std::min(wrapPi(r.angle), std::nextafter(kPi, 0.0)), r.cell});
  }

  // By angle bin; per bin, the cells holding returns of that bin.
  std::vector<std::pair<std::uint32_t, int>> cell_bins;
  for (std::size_t i = 0; i < returns_.size(); ++i) {
    const int b = angleBinOf(returns_[i].normal);
    bins_[static_cast<std::size_t>(b)].push_back(i);
    cell_bins.emplace_back(returns_[i].cell, b);
  }
  std::sort(cell_bins.begin(), cell_bins.end());
  cell_bins.erase(std::unique(cell_bins.begin(), cell_bins.end()), cell_bins.end());
  for (const auto& cb : cell_bins) cells_per_bin_[static_cast<std::size_t>(cb.second)] += 1.0;
  observed_ = std::max(1.0, static_cast<double>(e.countObserved()));
  // By offset, per bin.
  centre_ = 0.5 * (g.origin + g.maxCorner());
  by_offset_.resize(kAngleBins);
  for (int b = 0; b < kAngleBins; ++b) {
    const double theta = (b + 0.5) * kPi / kAngleBins;
    const Vec2 nb(std::cos(theta), std::sin(theta));
    std::vector<Keyed>& keyed = by_offset_[static_cast<std::size_t>(b)];
    for (std::size_t i : bins_[static_cast<std::size_t>(b)]) {
      const Vec2 p = returns_[i].at - centre_;
      keyed.push_back({nb.dot(p), i});
      radius_ = std::max(radius_, p.norm());
    }
    std::sort(keyed.begin(), keyed.end(), [](const Keyed& a, const Keyed& c) { return a.key < c.key; });
  }
  // By cell.
  by_cell_.resize(returns_.size());
  for (std::size_t i = 0; i < returns_.size(); ++i) by_cell_[i] = i;
  std::stable_sort(by_cell_.begin(), by_cell_.end(),
                   [&](std::size_t a, std::size_t b) { return returns_[a].cell < returns_[b].cell; });
}

template <class Fn>
void WeakReturns::forCell(std::uint32_t cell, Fn&& fn) const {
  auto it = std::lower_bound(by_cell_.begin(), by_cell_.end(), cell,
                             [&](std::size_t i, std::uint32_t c) { return returns_[i].cell < c; });
  for (; it != by_cell_.end() && returns_[*it].cell == cell; ++it)
    if (!fn(returns_[*it])) return;
}

bool WeakReturns::specific(std::uint32_t cell, double normal, double tol, double share) const {
  std::size_t all = 0, near = 0;
  forCell(cell, [&](const WeakReturn& r) {
    ++all;
    near += std::abs(angleDiff(r.normal, normal)) <= tol;
    return true;
  });
  return static_cast<double>(near) >= share * static_cast<double>(all);
}

bool WeakReturns::compatible(std::uint32_t cell, double normal, double tol) const {
  bool found = false;
  forCell(cell, [&](const WeakReturn& r) {
    found = std::abs(angleDiff(r.normal, normal)) <= tol;
    return !found;
  });
  return found;
}

double WeakReturns::background(double normal, int pad) const {
  const int centre = angleBinOf(normal);
  double sum = 0.0;
  for (int d = -pad; d <= pad; ++d) sum += cells_per_bin_[static_cast<std::size_t>(wrapBin(centre + d))];
  return std::min(1.0, sum / observed_);
}

int glassInBlock(const grid::GridGeometry& g, const std::vector<std::uint8_t>& label, int x, int y, int r) {
  int n = 0;
  for (int dy = -r; dy <= r; ++dy)
    for (int dx = -r; dx <= r; ++dx) n += g.contains(x + dx, y + dy) && isGlass(label[g.index(x + dx, y + dy)]);
  return n;
}

}  // namespace glassmap::glass::sparse
