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

IntegrationStats integrateCounts(const LaserLog& log, const BeamOptions& options, HitMissGrid& grid,
                                 const Progress& progress) {
  IntegrationStats stats;
  const GridGeometry& g = grid.geometry();
  for (std::size_t s = 0; s < log.scans.size(); ++s) {
    forEachBeam(log.scans[s], options, [&](const Beam& beam) {
      const bool end_inside = beam.hit && g.contains(g.cellAt(beam.to));
      stats.cells_traversed += traverse(g, beam.from, beam.to, [&](int x, int y, double t, bool last) {
        if (end_inside && last) {
          grid.addHit(x, y);
        } else if (countsMiss(beam, t * beam.range, options.miss_margin)) {
          grid.addMiss(x, y);
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

IntegrationStats integrateAngles(const LaserLog& log, const BeamOptions& options,
                                 AngleHistograms& histograms, const Progress& progress) {
  IntegrationStats stats;
  const GridGeometry& g = histograms.geometry();
  const int bins = histograms.bins();
  for (std::size_t s = 0; s < log.scans.size(); ++s) {
    forEachBeam(log.scans[s], options, [&](const Beam& beam) {
      const bool end_inside = beam.hit && g.contains(g.cellAt(beam.to));
      const int bin = angleBin(beam.angle, bins);
      stats.cells_traversed += traverse(g, beam.from, beam.to, [&](int x, int y, double t, bool last) {
        const std::int32_t id = histograms.find(x, y);
        if (id == AngleHistograms::kNone) return;
        if (end_inside && last) {
          histograms.addHit(id, bin);
        } else if (countsMiss(beam, t * beam.range, options.miss_margin)) {
          histograms.addMiss(id, bin);
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

}  // namespace glassmap::grid
