#include "glassmap/grid/scan_integration.hpp"

#include "glassmap/core/error.hpp"
#include "glassmap/geometry/vector_map.hpp"
#include "glassmap/grid/parallel_scans.hpp"
#include "glassmap/grid/traversal.hpp"

#include <tbb/parallel_reduce.h>

namespace glassmap::grid {

const char* toString(NoReturnMode mode) { return mode == NoReturnMode::Open ? "open" : "angular"; }

NoReturnMode parseNoReturnMode(const std::string& name) {
  for (NoReturnMode m : {NoReturnMode::Open, NoReturnMode::Angular})
    if (name == toString(m)) return m;
  throw Error("unknown no-return reading '" + name + "' (expected open or angular)", {}, 0, "no_returns");
}

std::shared_ptr<const BeamDirections> beamDirections(const LaserScan& scan) {
  // A few layouts per thread, newest first (a log has one or two; a pass may nest another log's).
  thread_local std::vector<std::shared_ptr<const BeamDirections>> cache;
  const std::size_t n = scan.ranges.size();
  for (std::size_t k = 0; k < cache.size(); ++k) {
    const BeamDirections& d = *cache[k];
    if (d.start_angle == scan.start_angle && d.angular_step == scan.angular_step && d.cos.size() == n) {
      if (k > 0) std::swap(cache[k], cache[0]);
      return cache[0];
    }
  }
  auto d = std::make_shared<BeamDirections>();
  d->start_angle = scan.start_angle;
  d->angular_step = scan.angular_step;
  d->cos.resize(n);
  d->sin.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double a = scan.beamAngle(i);
    d->cos[i] = std::cos(a);
    d->sin[i] = std::sin(a);
  }
  constexpr std::size_t kKept = 4;
  if (cache.size() == kKept) cache.pop_back();
  cache.insert(cache.begin(), std::move(d));
  return cache[0];
}

GridGeometry geometryForLog(const LaserLog& log, double resolution, const BeamOptions& options, double margin) {
  // Scans in parallel; a box's extension is a min and a max, the same whatever the split.
  tbb::enumerable_thread_specific<Eigen::AlignedBox2d> boxes;
  forScansInParallel(log, {}, boxes, [&](const LaserScan& scan, std::size_t, Eigen::AlignedBox2d& b) {
    b.extend(scan.laser_pose.t);
    forEachBeam(
        scan, options, [&](const Beam& beam) { b.extend(beam.to); }, passBeams(options));
  });
  Eigen::AlignedBox2d box;
  for (const Eigen::AlignedBox2d& b : boxes) box.extend(b);
  if (box.isEmpty()) throw Error("the log holds no scan to map");
  return coveringGeometry(box.min(), box.max(), resolution, margin);
}

namespace {

// A thread's part of a pass: its own counts (a grid or histogram counts) and statistics.
template <typename Counts>
struct Part {
  Counts counts;
  IntegrationStats stats;
};

// One pass over every beam of the log, scans in parallel: prepare(counts, beam) makes the beam's
// visitor into the thread's own counts, called visit(x, y, is_hit) for the end cell of a hit inside
// the grid (is_hit) and for each traversed cell that counts as a miss; the parts are then handed
// to merge(counts) one by one.
template <typename Counts, typename Make, typename Prepare, typename Merge>
IntegrationStats integratePass(const LaserLog& log, const BeamOptions& options, const GridGeometry& g,
                               const Progress& progress, Make make, Prepare prepare, Merge merge) {
  tbb::enumerable_thread_specific<Part<Counts>> parts([&] { return Part<Counts>{make(), {}}; });
  forScansInParallel(log, progress, parts, [&](const LaserScan& scan, std::size_t, Part<Counts>& part) {
    IntegrationStats& stats = part.stats;
    forEachBeam(
        scan, options,
        [&](const Beam& beam) {
          const bool end_inside = beam.hit && g.contains(g.cellAt(beam.to));
          auto visit = prepare(part.counts, beam);
          const MissTest misses(beam, options.miss_margin);
          stats.cells_traversed += traverse(g, beam.from, beam.to, [&](int x, int y, double t, bool last) {
            if (end_inside && last) {
              visit(x, y, true);
            } else if (misses(t)) {
              visit(x, y, false);
            }
          });
          ++stats.beams;
          stats.hit_beams += beam.hit ? 1 : 0;
        },
        passBeams(options));
    ++stats.scans;
  });
  IntegrationStats total;
  for (Part<Counts>& part : parts) {
    merge(std::move(part.counts));
    total += part.stats;
  }
  return total;
}

}  // namespace

IntegrationStats integrateCounts(const LaserLog& log, const BeamOptions& options, HitMissGrid& grid,
                                 const Progress& progress) {
  return integratePass<HitMissGrid>(
      log, options, grid.geometry(), progress, [&] { return HitMissGrid(grid.geometry()); },
      [](HitMissGrid& counts, const Beam&) {
        return [cursor = HitMissGrid::Cursor(counts)](int x, int y, bool hit) mutable {
          if (hit) {
            cursor.addHit(x, y);
          } else {
            cursor.addMiss(x, y);
          }
        };
      },
      [&](HitMissGrid&& part) { grid.merge(std::move(part)); });
}

IntegrationStats integrateAngles(const LaserLog& log, const BeamOptions& options, AngleHistograms& histograms,
                                 const Progress& progress) {
  const int bins = histograms.bins();
  return integratePass<std::vector<std::uint16_t>>(
      log, options, histograms.geometry(), progress, [&] { return histograms.emptyCounts(); },
      [&](std::vector<std::uint16_t>& counts, const Beam& beam) {
        return [&counts, &histograms, bin = angleBin(beam.angle, bins), cursor = AngleHistograms::Cursor(histograms)](
                   int x, int y, bool hit) mutable {
          const std::int32_t id = cursor.find(x, y);
          if (id == AngleHistograms::kNone) return;
          if (hit) {
            histograms.addHit(counts, id, bin);
          } else {
            histograms.addMiss(counts, id, bin);
          }
        };
      },
      [&](std::vector<std::uint16_t>&& part) { histograms.merge(part); });
}

}  // namespace glassmap::grid
