#include "glassmap/grid/scan_integration.hpp"

#include "glassmap/core/error.hpp"
#include "glassmap/geometry/vector_map.hpp"
#include "glassmap/grid/traversal.hpp"

namespace glassmap::grid {
namespace {

constexpr std::size_t kProgressEvery = 256;  // scans between progress calls

}  // namespace

GridGeometry geometryForLog(const LaserLog& log, double resolution, const BeamOptions& options,
                            double margin) {
  Box2 box;
  for (const LaserScan& scan : log.scans) {
    box.extend(scan.laser_pose.t);
    forEachBeam(scan, options, [&](const Beam& beam) { box.extend(beam.to); });
  }
  if (box.empty()) throw Error("the log holds no scan to map");
  return coveringGeometry(box.min, box.max, resolution, margin);
}

namespace {

// One pass over every beam of the log: visit(beam, x, y, is_hit) for the end cell of a hit inside
// the grid (is_hit) and for each traversed cell that counts as a miss. Both passes share it.
template <typename Prepare, typename Visit>
IntegrationStats integratePass(const LaserLog& log, const BeamOptions& options, const GridGeometry& g,
                               const Progress& progress, Prepare prepare, Visit visit) {
  IntegrationStats stats;
  for (std::size_t s = 0; s < log.scans.size(); ++s) {
    forEachBeam(log.scans[s], options, [&](const Beam& beam) {
      const bool end_inside = beam.hit && g.contains(g.cellAt(beam.to));
      const auto per_beam = prepare(beam);
      stats.cells_traversed += traverse(g, beam.from, beam.to, [&](int x, int y, double t, bool last) {
        if (end_inside && last) {
          visit(per_beam, x, y, true);
        } else if (countsMiss(beam, t * beam.range, options.miss_margin)) {
          visit(per_beam, x, y, false);
        }
      });
      ++stats.beams;
      stats.hit_beams += beam.hit ? 1 : 0;
    });
    ++stats.scans;
    if (progress && s % kProgressEvery == 0) progress(static_cast<double>(s) / log.scans.size());
  }
  if (progress) progress(1.0);
  return stats;
}

}  // namespace

IntegrationStats integrateCounts(const LaserLog& log, const BeamOptions& options, HitMissGrid& grid,
                                 const Progress& progress) {
  return integratePass(
      log, options, grid.geometry(), progress, [](const Beam&) { return 0; },
      [&](int, int x, int y, bool hit) {
        if (hit) {
          grid.addHit(x, y);
        } else {
          grid.addMiss(x, y);
        }
      });
}

IntegrationStats integrateAngles(const LaserLog& log, const BeamOptions& options,
                                 AngleHistograms& histograms, const Progress& progress) {
  const int bins = histograms.bins();
  return integratePass(
      log, options, histograms.geometry(), progress, [bins](const Beam& beam) { return angleBin(beam.angle, bins); },
      [&](int bin, int x, int y, bool hit) {
        const std::int32_t id = histograms.find(x, y);
        if (id == AngleHistograms::kNone) return;
        if (hit) {
          histograms.addHit(id, bin);
        } else {
          histograms.addMiss(id, bin);
        }
      });
}

}  // namespace glassmap::grid
