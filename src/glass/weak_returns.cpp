#include "weak_returns.hpp"

#include <algorithm>
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

// Returns and passes per candidate cell, exact for the cells `targets` marks: a pass is a
// returned beam that crosses the cell and ends at least `margin` beyond it. Only the beams whose
// walk over the targets' tiles meets one are walked (the others neither end in nor cross one).
void countPasses(const LaserLog& log, const grid::BeamOptions& beams, const CellEvidence& e, double margin,
                 const detail::MarkedTiles& targets, std::vector<std::uint32_t>& hits,
                 std::vector<std::uint32_t>& passes) {
  const grid::GridGeometry& g = e.geometry;
  const detail::CandidateIndex index(e);
  struct Tally {
    std::vector<std::uint32_t> hits, passes;
  };
  tbb::enumerable_thread_specific<Tally> tallies([&] {
    return Tally{std::vector<std::uint32_t>(e.cells.size(), 0), std::vector<std::uint32_t>(e.cells.size(), 0)};
  });
  grid::forScansInParallel(log, {}, tallies, [&](const LaserScan& scan, std::size_t, Tally& t) {
    grid::forEachBeam(scan, beams, [&](const grid::Beam& beam) {
      if (!beam.hit || !targets.near(beam.from, beam.to)) return;
      const double pass_until = beam.range - margin;
      grid::traverse(g, beam.from, beam.to, [&](int x, int y, double enter, bool last) {
        const std::int64_t id = index.find(x, y);
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

}  // namespace

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
    std::size_t c;
  };
  const double least_clearance = std::max(o.wall_clearance, 3.0 * o.range_sigma);
  std::vector<std::vector<Candidate>> per_scan(log.scanCount());
  tbb::enumerable_thread_specific<int> unused;
  grid::forScansInParallel(log, {}, unused, [&](const LaserScan& scan, std::size_t index, int&) {
    // Beyond this range a beam is wider than max_footprint cells: a cell's returns and passes then
    // mix the surfaces the beam grazes.
    const double max_range = o.max_footprint * g.resolution / std::max(std::abs(scan.angular_step), 1e-6);
    std::vector<Candidate>& out = per_scan[index];
    grid::forEachBeam(scan, beams, [&](const grid::Beam& beam) {
      if (!beam.hit || beam.range < o.min_range || beam.range > max_range) return;
      const auto cell = static_cast<std::uint32_t>(g.index(g.cellAt(beam.to)));
      if (wall_distance[cell] * g.resolution <= least_clearance) return;
      const std::int64_t id = e.candidate(cell);
      if (id < 0) return;
      const double sigma = std::hypot(o.range_sigma, o.range_sigma_rel * beam.range);
      if (wall_distance[cell] * g.resolution <= std::max(o.wall_clearance, 3.0 * sigma)) return;
      out.push_back({beam.to, beam.from, beam.angle, cell, static_cast<std::size_t>(id)});
    });
  });
  std::vector<Candidate> candidates;
  for (std::vector<Candidate>& c : per_scan) {
    candidates.insert(candidates.end(), c.begin(), c.end());
    c = {};
  }
  // Their cells' passes: a pass over the beams that cross them.
  detail::MarkedTiles targets(g, 8);
  for (const Candidate& r : candidates) {
    const grid::CellIndex at = g.cellOf(r.cell);
    targets.mark(at.x, at.y);
  }
  std::vector<std::uint32_t> hits, passes;
  if (!candidates.empty()) countPasses(log, beams, e, o.through_margin, targets, hits, passes);
  for (const Candidate& r : candidates) {
    if (passes[r.c] < static_cast<std::uint32_t>(o.min_through) ||
        hits[r.c] > o.max_hit_ratio * static_cast<double>(hits[r.c] + passes[r.c]))
      continue;
    returns_.push_back({r.at, r.from, std::min(wrapPi(r.angle), std::nextafter(kPi, 0.0)), r.cell});
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
