#include "glassmap/glass/opaque_glass.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "glass_tiles.hpp"
#include "glassmap/grid/parallel_scans.hpp"
#include "glassmap/grid/traversal.hpp"

namespace glassmap::glass {

OpaqueGlassStats relabelOpaqueGlass(const LaserLog& log, const grid::BeamOptions& beams, const OpaqueGlassOptions& o,
                                    CellEvidence& e) {
  OpaqueGlassStats stats;
  const grid::GridGeometry& g = e.geometry;
  // Glass cells get a slot; the pane normal of each from its label's angle bin.
  std::vector<bool> is_glass(g.cells(), false);
  std::vector<std::size_t> cells;  // ascending
  std::vector<Vec2> normals;
  for (std::size_t i = 0; i < g.cells(); ++i) {
    if (!isGlass(e.label[i])) continue;
    is_glass[i] = true;
    cells.push_back(i);
    const double a = glassBin(e.label[i]) * kPi / e.bins;  // bin b is centred on b * 180 / bins
    normals.emplace_back(std::cos(a), std::sin(a));
  }
  stats.glass_cells = cells.size();
  if (cells.empty()) return stats;

  // Per thread: passes and stops per glass cell. Integer sums: the result does not depend on how
  // the scans were shared out.
  struct Tally {
    std::vector<std::uint32_t> pass, stop, own;
  };
  tbb::enumerable_thread_specific<Tally> tallies([&] {
    return Tally{std::vector<std::uint32_t>(cells.size(), 0), std::vector<std::uint32_t>(cells.size(), 0),
                 std::vector<std::uint32_t>(cells.size(), 0)};
  });
  const detail::GlassTiles tiles(e);
  const detail::CandidateIndex slots(g, cells);  // glass cell -> its slot
  grid::forScansInParallel(log, {}, tallies, [&](const LaserScan& scan, std::size_t, Tally& t) {
    grid::forEachBeam(scan, beams, [&](const grid::Beam& beam) {
      if (!tiles.near(beam.from, beam.to)) return;
      // A beam that went through a pane may have been folded by it: beyond that pane, where its
      // straight continuation ends says nothing about what it crosses.
      auto slot = [&](int x, int y) { return static_cast<std::size_t>(slots.find(x, y)); };
      // A return in a glass cell itself.
      const grid::CellIndex end = g.cellAt(beam.to);
      if (beam.hit && g.contains(end) && is_glass[g.index(end)]) ++t.own[slot(end.x, end.y)];
      // The glass cells it crosses, up to where it leaves the first pane. The beam's terms are
      // worked out at its first glass cell (most beams near a pane cross none).
      bool in_glass = false;
      double beyond = 0.0;
      Vec2 dir = Vec2::Zero();
      grid::traverse(g, beam.from, beam.to, [&](int x, int y, double, bool last) {
        const std::size_t i = g.index(x, y);
        if (!is_glass[i]) return !in_glass;  // past the first pane: nothing more counts
        if (!in_glass) {
          const double sigma = std::hypot(o.range_sigma, o.range_sigma_rel * beam.range);
          beyond = std::max(o.beyond, 5.0 * sigma);
          dir = (beam.to - beam.from) / std::max(beam.range, 1e-9);
        }
        in_glass = true;
        if (last) return false;
        const std::size_t c = slot(x, y);
        const Vec2 n = dir.dot(normals[c]) >= 0.0 ? normals[c] : Vec2(-normals[c]);
        const double past = n.dot(beam.to - g.center(x, y));
        ++(!beam.hit || past >= beyond ? t.pass[c] : t.stop[c]);
        return true;
      });
    });
  });
  std::vector<std::uint32_t> pass(cells.size(), 0), stop(cells.size(), 0), own(cells.size(), 0);
  for (const Tally& t : tallies)
    for (std::size_t c = 0; c < cells.size(); ++c) {
      pass[c] += t.pass[c];
      stop[c] += t.stop[c];
      own[c] += t.own[c];
    }

  for (std::size_t c = 0; c < cells.size(); ++c) {
    const double crossings = static_cast<double>(pass[c] + stop[c]);
    // Returned by many beams and passed by none that came to it directly: nothing says it lets
    // light through (glass seen only through other glass, and the far walls behind it).
    const bool never_passed = pass[c] == 0 && own[c] >= static_cast<std::uint32_t>(o.min_unpassed_returns);
    if (crossings < o.min_crossings && !never_passed) continue;
    ++stats.decided;
    if (!never_passed && static_cast<double>(pass[c]) >= o.min_transmission * crossings) continue;
    const std::size_t i = cells[c];
    const std::int64_t id = e.candidate(static_cast<std::uint32_t>(i));
    std::uint8_t best = kEmpty;
    if (id >= 0) {
      const float* cost = e.costs(static_cast<std::size_t>(id));
      best = cost[kOccupied] < cost[kEmpty] ? kOccupied : kEmpty;
    }
    e.label[i] = best;
    ++stats.relabelled;
  }
  return stats;
}

}  // namespace glassmap::glass
