#include "glassmap/glass/sparse_panes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <vector>

#include <boost/math/special_functions/beta.hpp>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "glassmap/grid/angle_histograms.hpp"
#include "glassmap/grid/traversal.hpp"

namespace glassmap::glass {
namespace {

constexpr int kAngleBins = 180;  // 1-degree bins of the normal angle over [0, 180)

// A return from a cell most beams pass, and the direction it came along (its pane's normal).
struct WeakReturn {
  Vec2 at;            // the reading [m]
  Vec2 from;          // the laser [m]
  double normal;      // beam direction modulo pi, in [0, pi)
  std::uint32_t cell; // linear index of the reading's cell
};

// The line n . p = rho, n = (cos angle, sin angle), angle in [0, pi).
struct Line {
  double angle = 0.0;
  double rho = 0.0;
  Vec2 normal() const { return {std::cos(angle), std::sin(angle)}; }
  Vec2 tangent() const { return {-std::sin(angle), std::cos(angle)}; }
};

// A run of weak returns along a line, from s0 to s1 along its tangent.
struct Run {
  Line line;
  double s0 = 0.0, s1 = 0.0;
  std::vector<std::size_t> returns;
  Vec2 end(double s) const { return line.rho * line.normal() + s * line.tangent(); }
};

// An angle modulo pi, in [0, pi).
double wrapPi(double a) { return a - kPi * std::floor(a / kPi); }

// Difference of two normal angles in [0, pi), modulo pi: in [-pi/2, pi/2].
double angleDiff(double a, double b) {
  const double d = a - b;
  return d > 0.5 * kPi ? d - kPi : (d < -0.5 * kPi ? d + kPi : d);
}

// Returns and passes per candidate cell: a pass is a returned beam that crosses the cell and ends
// at least `margin` beyond it.
// Candidate number of every cell, held in 16 x 16 tiles allocated where candidates are.
class CandidateIndex {
 public:
  explicit CandidateIndex(const CellEvidence& e)
      : g_(e.geometry), tiles_x_((g_.width + 15) / 16), tiles_(static_cast<std::size_t>(tiles_x_) * ((g_.height + 15) / 16)) {
    for (std::size_t i = 0; i < e.cells.size(); ++i) {
      const grid::CellIndex c = g_.cellOf(e.cells[i]);
      auto& tile = tiles_[tileOf(c.x, c.y)];
      if (tile.empty()) tile.assign(256, -1);
      tile[static_cast<std::size_t>(((c.y & 15) << 4) | (c.x & 15))] = static_cast<std::int32_t>(i);
    }
  }
  /// Candidate number of cell (x, y) inside the grid, or -1.
  std::int32_t find(int x, int y) const {
    const auto& tile = tiles_[tileOf(x, y)];
    return tile.empty() ? -1 : tile[static_cast<std::size_t>(((y & 15) << 4) | (x & 15))];
  }

 private:
  std::size_t tileOf(int x, int y) const { return static_cast<std::size_t>(y >> 4) * tiles_x_ + (x >> 4); }
  const grid::GridGeometry& g_;
  std::size_t tiles_x_;
  std::vector<std::vector<std::int32_t>> tiles_;
};

void countPasses(const LaserLog& log, const grid::BeamOptions& beams, const CellEvidence& e, double margin,
                 std::vector<std::uint32_t>& hits, std::vector<std::uint32_t>& passes) {
  const grid::GridGeometry& g = e.geometry;
  const CandidateIndex index(e);
  struct Tally {
    std::vector<std::uint32_t> hits, passes;
  };
  tbb::enumerable_thread_specific<Tally> tallies([&] {
    return Tally{std::vector<std::uint32_t>(e.cells.size(), 0), std::vector<std::uint32_t>(e.cells.size(), 0)};
  });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, log.scans.size(), 16), [&](const auto& range) {
    Tally& t = tallies.local();
    for (std::size_t s = range.begin(); s != range.end(); ++s)
      grid::forEachBeam(log.scans[s], beams, [&](const grid::Beam& beam) {
        if (!beam.hit) return;
        const double pass_until = beam.range - margin;
        grid::traverse(g, beam.from, beam.to, [&](int x, int y, double enter, bool last) {
          const std::int32_t id = index.find(x, y);
          if (id < 0) return;
          const auto c = static_cast<std::size_t>(id);
          if (last)
            ++t.hits[c];
          else if (enter * beam.range < pass_until)
            ++t.passes[c];
        });
      });
  });
  hits.assign(e.cells.size(), 0);
  passes.assign(e.cells.size(), 0);
  for (const Tally& t : tallies)
    for (std::size_t i = 0; i < e.cells.size(); ++i) {
      hits[i] += t.hits[i];
      passes[i] += t.passes[i];
    }
}

// Chamfer distance (3 per cell step, 4 per diagonal step, capped at 255) of every cell to the
// nearest occupied cell.
std::vector<std::uint8_t> distanceToWalls(const CellEvidence& e) {
  const grid::GridGeometry& g = e.geometry;
  std::vector<std::uint8_t> d(g.cells(), 255);
  for (std::size_t i = 0; i < d.size(); ++i)
    if (e.label[i] == kOccupied) d[i] = 0;
  auto relax = [&](int x, int y, int dx, int dy, int cost) {
    if (!g.contains(x + dx, y + dy)) return;
    std::uint8_t& here = d[g.index(x, y)];
    here = static_cast<std::uint8_t>(std::min<int>(here, d[g.index(x + dx, y + dy)] + cost));
  };
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      relax(x, y, -1, 0, 3);
      relax(x, y, 0, -1, 3);
      relax(x, y, -1, -1, 4);
      relax(x, y, 1, -1, 4);
    }
  for (int y = g.height - 1; y >= 0; --y)
    for (int x = g.width - 1; x >= 0; --x) {
      relax(x, y, 1, 0, 3);
      relax(x, y, 0, 1, 3);
      relax(x, y, 1, 1, 4);
      relax(x, y, -1, 1, 4);
    }
  return d;
}

// Line votes: (1-degree angle bin, offset bin) per weak return, the angle axis padded by `pad` bins
// on both sides with the wrapped votes (angle + pi is the same line with the offset negated), so
// that a window around any angle sums every vote within it.
class Votes {
 public:
  Votes(double rho_max, double rho_step, int pad)
      : step_(rho_step), pad_(pad), half_(static_cast<int>(std::ceil(rho_max / rho_step))),
        rows_(kAngleBins + 2 * pad), cols_(2 * half_ + 1), sum_(static_cast<std::size_t>(rows_ + 1) * (cols_ + 1), 0) {
    count_.assign(static_cast<std::size_t>(rows_) * cols_, 0);
  }
  void add(double angle, double rho) {
    const int b = std::clamp(static_cast<int>(angle * kAngleBins / kPi), 0, kAngleBins - 1);
    put(b + pad_, rho);
    if (b < pad_) put(b + kAngleBins + pad_, -rho);
    if (b >= kAngleBins - pad_) put(b - kAngleBins + pad_, -rho);
  }
  // Summed-area table of the counts.
  void integrate() {
    for (int r = 0; r < rows_; ++r)
      for (int c = 0; c < cols_; ++c)
        sum_[idx(r + 1, c + 1)] = count_[static_cast<std::size_t>(r) * cols_ + c] + sum_[idx(r, c + 1)] +
                                  sum_[idx(r + 1, c)] - sum_[idx(r, c)];
  }
  // Votes within +-wa angle bins and +-wr offset bins of (row, col).
  std::int64_t window(int row, int col, int wa, int wr) const {
    const int r0 = std::max(0, row - wa), r1 = std::min(rows_, row + wa + 1);
    const int c0 = std::max(0, col - wr), c1 = std::min(cols_, col + wr + 1);
    return sum_[idx(r1, c1)] - sum_[idx(r0, c1)] - sum_[idx(r1, c0)] + sum_[idx(r0, c0)];
  }
  int rows() const { return rows_; }
  int cols() const { return cols_; }
  int pad() const { return pad_; }
  Line line(int row, int col) const {
    return {(row - pad_ + 0.5) * kPi / kAngleBins, (col - half_) * step_};
  }

 private:
  void put(int row, double rho) {
    const int c = static_cast<int>(std::lround(rho / step_)) + half_;
    if (c >= 0 && c < cols_) ++count_[static_cast<std::size_t>(row) * cols_ + c];
  }
  std::size_t idx(int r, int c) const { return static_cast<std::size_t>(r) * (cols_ + 1) + c; }
  double step_;
  int pad_, half_, rows_, cols_;
  std::vector<std::int64_t> sum_;
  std::vector<std::int32_t> count_;
};

// Unused returns compatible with `line` (angle within tol_a, offset within tol_r), from the
// returns bucketed by angle bin.
std::vector<std::size_t> gather(const std::vector<WeakReturn>& w, const std::vector<std::vector<std::size_t>>& bucket,
                                const std::vector<bool>& used, const Line& line, double tol_a, double tol_r) {
  std::vector<std::size_t> out;
  const int centre = static_cast<int>(line.angle * kAngleBins / kPi);
  const int span = static_cast<int>(std::ceil(tol_a * kAngleBins / kPi)) + 1;
  const Vec2 n = line.normal();
  for (int d = -span; d <= span; ++d) {
    const int b = ((centre + d) % kAngleBins + kAngleBins) % kAngleBins;
    for (std::size_t i : bucket[static_cast<std::size_t>(b)]) {
      if (used[i] || std::abs(angleDiff(w[i].normal, line.angle)) > tol_a) continue;
      if (std::abs(n.dot(w[i].at) - line.rho) <= tol_r) out.push_back(i);
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

// The line through returns `idx`: their principal axis when they spread over a metre and it agrees
// with their beams, else the mean beam direction; the offset is the median.
Line fitLine(const std::vector<WeakReturn>& w, const std::vector<std::size_t>& idx, const Line& seed, double tol_a) {
  double c2 = 0, s2 = 0, mx = 0, my = 0;
  for (std::size_t i : idx) {
    c2 += std::cos(2.0 * angleDiff(w[i].normal, seed.angle));
    s2 += std::sin(2.0 * angleDiff(w[i].normal, seed.angle));
    mx += w[i].at.x();
    my += w[i].at.y();
  }
  const double n = static_cast<double>(idx.size());
  mx /= n;
  my /= n;
  double angle = seed.angle + 0.5 * std::atan2(s2, c2);
  double sxx = 0, sxy = 0, syy = 0;
  for (std::size_t i : idx) {
    const double dx = w[i].at.x() - mx, dy = w[i].at.y() - my;
    sxx += dx * dx;
    sxy += dx * dy;
    syy += dy * dy;
  }
  const double axis = 0.5 * std::atan2(2.0 * sxy, sxx - syy);  // direction of the major axis
  const double spread = 0.5 * (sxx + syy) + std::sqrt(0.25 * (sxx - syy) * (sxx - syy) + sxy * sxy);
  const double pca_normal = wrapPi(axis + 0.5 * kPi);
  angle = wrapPi(angle);
  if (std::sqrt(spread / n) > 0.3 && std::abs(angleDiff(pca_normal, angle)) <= tol_a) angle = pca_normal;
  Line line;
  line.angle = angle;
  std::vector<double> rho;
  rho.reserve(idx.size());
  const Vec2 nn = line.normal();
  for (std::size_t i : idx) rho.push_back(nn.dot(w[i].at));
  std::nth_element(rho.begin(), rho.begin() + static_cast<std::ptrdiff_t>(rho.size() / 2), rho.end());
  line.rho = rho[rho.size() / 2];
  return line;
}

// Runs of returns `idx` along `line`, split at gaps over max_gap, or over gap_factor times the
// median spacing of the cells the returns fill along the line (a pane's ends are where its returns
// stop; a stray return a metre on would otherwise stretch it).
std::vector<Run> splitRuns(const std::vector<WeakReturn>& w, std::vector<std::size_t> idx, const Line& line,
                           double cell, double max_gap, double gap_factor) {
  const Vec2 t = line.tangent();
  std::sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) { return t.dot(w[a].at) < t.dot(w[b].at); });
  std::vector<double> filled;  // cells along the line that hold returns
  for (std::size_t i : idx) {
    const double q = std::floor(t.dot(w[i].at) / cell);
    if (filled.empty() || q != filled.back()) filled.push_back(q);
  }
  std::vector<double> gaps;
  for (std::size_t k = 1; k < filled.size(); ++k) gaps.push_back(filled[k] - filled[k - 1]);
  double split = max_gap;
  if (!gaps.empty()) {
    std::nth_element(gaps.begin(), gaps.begin() + static_cast<std::ptrdiff_t>(gaps.size() / 2), gaps.end());
    split = std::min(max_gap, cell * std::max(3.0, gap_factor * gaps[gaps.size() / 2]));
  }
  std::vector<Run> runs;
  for (std::size_t i : idx) {
    const double s = t.dot(w[i].at);
    if (runs.empty() || s - runs.back().s1 > split) runs.push_back(Run{line, s, s, {}});
    runs.back().s1 = s;
    runs.back().returns.push_back(i);
  }
  return runs;
}

// log10 of P(X >= k) for X ~ Binomial(n, p).
double log10BinomialTail(int k, int n, double p) {
  if (k <= 0) return 0.0;
  if (k > n) n = k;
  if (p >= 1.0) return 0.0;
  const double tail = boost::math::ibeta(static_cast<double>(k), static_cast<double>(n - k + 1), p);
  return tail > 0.0 ? std::log10(tail) : -std::numeric_limits<double>::infinity();
}

// Per run: returned beams that pass the run and end at least `beyond` past it, and beams that
// return on it (within `band`) or just behind it.
template <class Beyond>
void countCrossings(const LaserLog& log, const grid::BeamOptions& beams, const std::vector<Run>& runs, double band,
                    Beyond&& beyond_at, std::vector<std::uint64_t>& pass, std::vector<std::uint64_t>& hit) {
  struct Tally {
    std::vector<std::uint64_t> pass, hit;
  };
  tbb::enumerable_thread_specific<Tally> tallies(
      [&] { return Tally{std::vector<std::uint64_t>(runs.size(), 0), std::vector<std::uint64_t>(runs.size(), 0)}; });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, log.scans.size(), 16), [&](const auto& range) {
    Tally& t = tallies.local();
    for (std::size_t s = range.begin(); s != range.end(); ++s)
      grid::forEachBeam(log.scans[s], beams, [&](const grid::Beam& beam) {
        if (!beam.hit) return;
        const double beyond = beyond_at(beam.range);
        for (std::size_t r = 0; r < runs.size(); ++r) {
          const Vec2 n = runs[r].line.normal(), tg = runs[r].line.tangent();
          const double f = n.dot(beam.from) - runs[r].line.rho, g = n.dot(beam.to) - runs[r].line.rho;
          if (std::abs(g) <= band) {
            const double along = tg.dot(beam.to);
            if (along >= runs[r].s0 && along <= runs[r].s1 && std::abs(f) > band) ++t.hit[r];
          } else if ((f > 0) != (g > 0)) {
            // Crossed: a pass when it ends well beyond, else it stopped just behind (a wall's face).
            const double along = tg.dot(beam.from + (f / (f - g)) * (beam.to - beam.from));
            if (along >= runs[r].s0 && along <= runs[r].s1) ++(std::abs(g) >= beyond ? t.pass[r] : t.hit[r]);
          }
        }
      });
  });
  pass.assign(runs.size(), 0);
  hit.assign(runs.size(), 0);
  for (const Tally& t : tallies)
    for (std::size_t r = 0; r < runs.size(); ++r) {
      pass[r] += t.pass[r];
      hit[r] += t.hit[r];
    }
}

// Calls visit(linear cell index) for the cells of a run's line, half a cell past either end.
template <class Visit>
void forRunCells(const grid::GridGeometry& g, const Run& run, Visit&& visit) {
  const double half = 0.5 * g.resolution;
  grid::traverse(g, run.end(run.s0 - half), run.end(run.s1 + half),
                 [&](int x, int y, double, bool) { visit(g.index(x, y)); });
}

// True when most of the run's returns crossed another pane of `panes` (labels with the candidate
// runs drawn in; a glass cell with at least min_pane_cells glass cells in its 5 x 5 block) at least
// glass_margin before the return. Beyond a pane, mirror images (a wall seen via the pane at the
// wall's normal) and walls seen through it at grazing incidence (shifted sideways by up to the
// pane's thickness, they land in front of themselves) have the signature of a faint pane.
bool seenThroughAnotherPane(const std::vector<WeakReturn>& w, const Run& run, const CellEvidence& panes,
                            const SparsePaneOptions& o) {
  const grid::GridGeometry& g = panes.geometry;
  auto isPane = [&](int x, int y) {
    int n = 0;
    for (int dy = -2; dy <= 2; ++dy)
      for (int dx = -2; dx <= 2; ++dx) n += g.contains(x + dx, y + dy) && isGlass(panes.label[g.index(x + dx, y + dy)]);
    return n >= o.min_pane_cells;
  };
  std::size_t via = 0;
  for (std::size_t i : run.returns) {
    const double range = (w[i].at - w[i].from).norm();
    bool crossed = false;
    grid::traverse(g, w[i].from, w[i].at, [&](int x, int y, double enter, bool) {
      if (enter * range >= range - o.glass_margin) return false;
      crossed = isGlass(panes.label[g.index(x, y)]) && isPane(x, y);
      return !crossed;
    });
    via += crossed;
  }
  return static_cast<double>(via) >= o.max_via * static_cast<double>(run.returns.size());
}

}  // namespace

SparsePaneStats findSparsePanes(const LaserLog& log, const grid::BeamOptions& beams, const SparsePaneOptions& o,
                                CellEvidence& e) {
  SparsePaneStats stats;
  const grid::GridGeometry& g = e.geometry;
  if (e.cells.empty() || log.scans.empty()) return stats;
  const double tol_r = std::max(o.offset_tol, 2.5 * o.range_sigma);
  const double tol_a = deg2rad(o.angle_tol_deg);

  // Weak returns: from cells most beams pass.
  std::vector<std::uint32_t> hits, passes;
  countPasses(log, beams, e, o.through_margin, hits, passes);
  // Distance to the nearest occupied cell: the ends and corners of walls, seen past from most
  // directions and hit from a few, and the noise-spread front of a wall seen at grazing incidence
  // look like faint panes too.
  const std::vector<std::uint8_t> wall_distance = distanceToWalls(e);
  auto sigmaAt = [&](double range) { return std::hypot(o.range_sigma, o.range_sigma_rel * range); };
  std::vector<WeakReturn> weak;
  for (const LaserScan& scan : log.scans)
    grid::forEachBeam(scan, beams, [&](const grid::Beam& beam) {
      if (!beam.hit || beam.range < o.min_range) return;
      const auto cell = static_cast<std::uint32_t>(g.index(g.cellAt(beam.to)));
      const std::int64_t id = e.candidate(cell);
      if (id < 0) return;
      const auto c = static_cast<std::size_t>(id);
      const double clearance = std::max(o.wall_clearance, 3.0 * sigmaAt(beam.range));
      if (wall_distance[cell] * g.resolution / 3.0 <= clearance || passes[c] < static_cast<std::uint32_t>(o.min_through) ||
          hits[c] > o.max_hit_ratio * static_cast<double>(hits[c] + passes[c]))
        return;
      weak.push_back({beam.to, beam.from, std::min(wrapPi(beam.angle), std::nextafter(kPi, 0.0)), cell});
    });
  stats.weak_returns = weak.size();
  if (weak.size() < static_cast<std::size_t>(o.min_returns)) return stats;

  // Background: per angle bin, the cells holding weak returns of that bin, over the observed cells.
  std::vector<std::vector<std::size_t>> bucket(kAngleBins);
  std::vector<std::pair<std::uint32_t, int>> cell_bins;
  for (std::size_t i = 0; i < weak.size(); ++i) {
    const int b = std::min(kAngleBins - 1, static_cast<int>(weak[i].normal * kAngleBins / kPi));
    bucket[static_cast<std::size_t>(b)].push_back(i);
    cell_bins.emplace_back(weak[i].cell, b);
  }
  std::sort(cell_bins.begin(), cell_bins.end());
  cell_bins.erase(std::unique(cell_bins.begin(), cell_bins.end()), cell_bins.end());
  std::vector<double> cells_per_bin(kAngleBins, 0.0);
  for (const auto& cb : cell_bins) cells_per_bin[static_cast<std::size_t>(cb.second)] += 1.0;
  const double observed = static_cast<double>(e.countObserved());
  const int pad = static_cast<int>(std::ceil(o.angle_tol_deg));
  auto background = [&](const Line& line) {
    const int centre = static_cast<int>(line.angle * kAngleBins / kPi);
    double sum = 0.0;
    for (int d = -pad; d <= pad; ++d) sum += cells_per_bin[static_cast<std::size_t>(((centre + d) % kAngleBins + kAngleBins) % kAngleBins)];
    return std::min(1.0, sum / std::max(1.0, observed));
  };

  // Weak returns by cell; a cell is specific to a normal when most of its returns came within
  // specific_tol of it.
  std::vector<std::size_t> by_cell(weak.size());
  for (std::size_t i = 0; i < weak.size(); ++i) by_cell[i] = i;
  std::stable_sort(by_cell.begin(), by_cell.end(),
                   [&](std::size_t a, std::size_t b) { return weak[a].cell < weak[b].cell; });
  const double specific_tol = deg2rad(o.specific_tol_deg);
  auto specific = [&](std::uint32_t cell, double normal) {
    auto it = std::lower_bound(by_cell.begin(), by_cell.end(), cell,
                               [&](std::size_t i, std::uint32_t c) { return weak[i].cell < c; });
    std::size_t all = 0, near = 0;
    for (; it != by_cell.end() && weak[*it].cell == cell; ++it) {
      ++all;
      near += std::abs(angleDiff(weak[*it].normal, normal)) <= specific_tol;
    }
    return static_cast<double>(near) >= o.min_specific * static_cast<double>(all);
  };
  auto compatible = [&](std::uint32_t cell, double normal) {
    auto it = std::lower_bound(by_cell.begin(), by_cell.end(), cell,
                               [&](std::size_t i, std::uint32_t c) { return weak[i].cell < c; });
    for (; it != by_cell.end() && weak[*it].cell == cell; ++it)
      if (std::abs(angleDiff(weak[*it].normal, normal)) <= tol_a) return true;
    return false;
  };
  // The share of observed cells around a run (within `around`, off its band) that hold a weak return
  // compatible with its line: weak returns gather near surfaces, far above the floor's average.
  auto localBackground = [&](const Run& run) {
    const Vec2 n = run.line.normal(), t = run.line.tangent();
    const double m = o.background_margin;
    Vec2 lo = run.end(run.s0 - m) - m * n, hi = lo;
    const Vec2 corners[] = {run.end(run.s0 - m) + m * n, run.end(run.s1 + m) - m * n, run.end(run.s1 + m) + m * n};
    for (const Vec2& c : corners) {
      lo = lo.cwiseMin(c);
      hi = hi.cwiseMax(c);
    }
    const grid::CellIndex a = g.cellAt(lo), b = g.cellAt(hi);
    double seen = 0.0, holding = 0.0;
    for (int y = std::max(0, a.y); y <= std::min(g.height - 1, b.y); ++y)
      for (int x = std::max(0, a.x); x <= std::min(g.width - 1, b.x); ++x) {
        const Vec2 c = g.center(x, y);
        const double d = std::abs(n.dot(c) - run.line.rho), along = t.dot(c);
        if (d <= tol_r || d > m || along < run.s0 - m || along > run.s1 + m) continue;
        const std::size_t i = g.index(x, y);
        if (e.label[i] == kUnknown) continue;
        seen += 1.0;
        holding += compatible(static_cast<std::uint32_t>(i), run.line.angle);
      }
    return seen > 0.0 ? holding / seen : 0.0;
  };

  // Votes, relative to the grid's centre; local maxima of the windowed votes, strongest first.
  const Vec2 centre = 0.5 * (g.origin + g.maxCorner());
  const double rho_max = 0.5 * (g.maxCorner() - g.origin).norm() + 1.0;
  Votes votes(rho_max, g.resolution, pad);
  for (const WeakReturn& r : weak) {
    const double a = r.normal;
    votes.add(a, Vec2(std::cos(a), std::sin(a)).dot(r.at - centre));
  }
  votes.integrate();
  const int wr = std::max(1, static_cast<int>(std::ceil(tol_r / g.resolution)));
  struct Peak {
    std::int64_t votes;
    int row, col;
  };
  std::vector<Peak> peaks;
  for (int row = pad; row < pad + kAngleBins; ++row)
    for (int col = 0; col < votes.cols(); ++col) {
      const std::int64_t v = votes.window(row, col, pad, wr);
      if (v < o.min_returns) continue;
      bool maximum = true;
      for (int dr = -1; dr <= 1 && maximum; ++dr)
        for (int dc = -1; dc <= 1 && maximum; ++dc)
          if ((dr || dc) && row + dr >= 0 && row + dr < votes.rows() && col + dc >= 0 && col + dc < votes.cols())
            maximum = votes.window(row + dr, col + dc, pad, wr) <= v;
      if (maximum) peaks.push_back({v, row, col});
    }
  std::stable_sort(peaks.begin(), peaks.end(), [](const Peak& a, const Peak& b) { return a.votes > b.votes; });

  // Runs along each peak's line; a contrario against the background of its direction.
  const double diagonal_cells = (g.maxCorner() - g.origin).norm() / g.resolution;
  const double log10_tests = std::log10(static_cast<double>(kAngleBins) * votes.cols()) + 2.0 * std::log10(diagonal_cells);
  const double band_cells = std::max(1.0, 2.0 * tol_r / g.resolution);
  std::vector<bool> used(weak.size(), false);
  std::vector<Run> runs;
  for (const Peak& peak : peaks) {
    Line seed = votes.line(peak.row, peak.col);
    seed.rho += seed.normal().dot(centre);  // the votes are relative to the grid's centre
    std::vector<std::size_t> idx = gather(weak, bucket, used, seed, tol_a, tol_r);
    if (idx.size() < static_cast<std::size_t>(o.min_returns)) continue;
    const Line line = fitLine(weak, idx, seed, tol_a);
    idx = gather(weak, bucket, used, line, tol_a, tol_r);
    if (idx.size() < static_cast<std::size_t>(o.min_returns)) continue;
    for (std::size_t i : idx) used[i] = true;
    // A pane cell returns only near its normal; a cell that returns to beams of every direction is
    // a corner, a post or an edge, and a few of those line up with any direction by chance.
    idx.erase(std::remove_if(idx.begin(), idx.end(),
                             [&](std::size_t i) { return !specific(weak[i].cell, line.angle); }),
              idx.end());
    const double p = background(line);
    for (Run& run : splitRuns(weak, idx, line, g.resolution, o.max_gap, o.gap_factor)) {
      if (run.returns.size() < static_cast<std::size_t>(o.min_returns) || run.s1 - run.s0 < o.min_length) continue;
      ++stats.runs_tested;
      std::vector<std::uint32_t> cells;
      for (std::size_t i : run.returns) cells.push_back(weak[i].cell);
      std::sort(cells.begin(), cells.end());
      const int k = static_cast<int>(std::unique(cells.begin(), cells.end()) - cells.begin());
      const int n = static_cast<int>(std::ceil(((run.s1 - run.s0) / g.resolution + 1.0) * band_cells));
      if (log10_tests + log10BinomialTail(k, n, std::max(p, localBackground(run))) >= o.log10_max_nfa) {
        ++stats.rejected_chance;
        continue;
      }
      runs.push_back(std::move(run));
    }
  }

  // Glass is crossed: most beams that meet the run pass it and end well beyond.
  std::vector<std::uint64_t> pass, hit;
  countCrossings(
      log, beams, runs, tol_r, [&](double range) { return std::max(o.beyond, 5.0 * sigmaAt(range)); }, pass, hit);
  std::vector<Run> seen_through;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    const double total = static_cast<double>(pass[r] + hit[r]);
    if (pass[r] < static_cast<std::uint64_t>(o.min_returns) || static_cast<double>(pass[r]) < o.min_transmission * total) {
      ++stats.rejected_opaque;
      continue;
    }
    seen_through.push_back(std::move(runs[r]));
  }

  // Not seen through another pane: the labels with every candidate drawn in as glass.
  CellEvidence panes;
  panes.geometry = g;
  panes.bins = e.bins;
  panes.num_labels = e.num_labels;
  panes.label = e.label;
  for (const Run& run : seen_through) {
    const auto l = static_cast<std::uint8_t>(glassLabel(grid::angleBin(run.line.angle, e.bins)));
    forRunCells(g, run, [&](std::size_t i) {
      if (panes.label[i] == kEmpty) panes.label[i] = l;
    });
  }
  for (const Run& run : seen_through) {
    if (seenThroughAnotherPane(weak, run, panes, o)) {
      ++stats.rejected_through;
      continue;
    }
    ++stats.panes;
    stats.metres += run.s1 - run.s0;
    if (std::getenv("GM_DEBUG_SPARSE")) {
      const Vec2 a = run.end(run.s0), b = run.end(run.s1);
      std::fprintf(stderr, "pane %.2f,%.2f -> %.2f,%.2f angle %.1f returns %zu\n", a.x(), a.y(), b.x(), b.y(),
                   rad2deg(run.line.angle), run.returns.size());
      for (std::size_t i : run.returns)
        std::fprintf(stderr, "   ret %.2f,%.2f from %.2f,%.2f n %.1f\n", weak[i].at.x(), weak[i].at.y(), weak[i].from.x(),
                     weak[i].from.y(), rad2deg(weak[i].normal));
    }
    const auto l = static_cast<std::uint8_t>(glassLabel(grid::angleBin(run.line.angle, e.bins)));
    forRunCells(g, run, [&](std::size_t i) {
      if (e.label[i] != kEmpty) return;
      e.label[i] = l;
      ++stats.cells_labelled;
    });
  }
  return stats;
}

}  // namespace glassmap::glass
