#include "glassmap/glass/mapping.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>

#include "glassmap/core/error.hpp"
#include "glassmap/grid/no_returns.hpp"

namespace glassmap::glass {
namespace {

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

const char* toString(Method m) { return m == Method::Heuristic ? "heuristic" : "direct"; }

Method parseMethod(const std::string& name) {
  if (name == "heuristic") return Method::Heuristic;
  if (name == "direct") return Method::Direct;
  throw Error("unknown method '" + name + "' (expected heuristic or direct)", {}, 0, "method");
}

MappingResult mapLog(const LaserLog& log, const MappingOptions& o,
                     const std::function<void(const char*, double)>& progress) {
  const double bins_real = 180.0 / o.angle_bin_deg;
  const int bins = static_cast<int>(std::lround(bins_real));
  if (!(o.angle_bin_deg > 0.0) || std::abs(bins_real - bins) > 1e-9 || bins > 235) {
    throw Error("angle bin width must divide 180 deg into at most 235 bins", {}, 0, "angle_bin_deg");
  }
  if (log.scanCount() == 0) throw Error("the log holds no scan to map");
  MappingResult result;
  MappingStats& st = result.stats;
  auto report = [&](const char* stage) -> grid::Progress {
    if (!progress) return {};
    return [&progress, stage](double f) { progress(stage, f); };
  };

  auto t0 = std::chrono::steady_clock::now();
  const grid::GridGeometry geometry = grid::geometryForLog(log, o.resolution, o.beams, o.margin);
  const double cells = static_cast<double>(geometry.width) * static_cast<double>(geometry.height);
  const double need = cells * kDenseBytesPerCell;
  if (need > static_cast<double>(o.max_memory_bytes)) {
    char text[320];
    std::snprintf(text, sizeof text,
                  "the grid of %d x %d cells at %.3g m would need about %.0f MB (%.0f bytes per cell), over "
                  "the limit of %.0f MB: raise the limit (--max-memory), use a coarser resolution, or check "
                  "the log for poses far outside the building",
                  geometry.width, geometry.height, o.resolution, need / 1e6, kDenseBytesPerCell,
                  static_cast<double>(o.max_memory_bytes) / 1e6);
    throw Error(text, {}, 0, "max_memory");
  }
  grid::HitMissGrid counts(geometry);
  const grid::IntegrationStats pass1 = grid::integrateCounts(log, o.beams, counts, report("counts"));
  st.scans = pass1.scans;
  st.beams = pass1.beams;
  st.hit_beams = pass1.hit_beams;
  st.cells_traversed = pass1.cells_traversed;
  st.seconds_counts = secondsSince(t0);

  t0 = std::chrono::steady_clock::now();
  grid::AngleHistograms hist(counts, bins);
  // No-return readings cross only what returned nothing their way (grid/no_returns.hpp); their
  // misses go into the standard occupancy map before the direct classifier reads d_real from it.
  grid::integrateNoReturns(log, o.beams, counts, hist);
  SigmoidSums sums;
  if (o.method == Method::Direct) {
    sums = integrateSigmoid(log, o.beams, counts, o.occupancy, hist, o.direct, nullptr, report("angles"));
  } else {
    grid::integrateAngles(log, o.beams, hist, report("angles"));
  }
  st.seconds_angles = secondsSince(t0);

  t0 = std::chrono::steady_clock::now();
  result.evidence = o.method == Method::Heuristic ? classifyHeuristic(counts, hist, o.heuristic)
                                                  : classifyDirect(counts, hist, sums, o.direct, o.beams.miss_margin);
  st.seconds_classify = secondsSince(t0);

  st.observed_cells = counts.observedCells();
  st.candidate_cells = hist.size();
  st.glass_cells = result.evidence.countGlass();
  st.occupied_cells = result.evidence.countOccupied();
  st.state_bytes =
      counts.bytes() + hist.bytes() + (sums.log_occ.capacity() + sums.log_glass.capacity()) * sizeof(float);
  st.bytes_per_observed_cell =
      st.observed_cells ? static_cast<double>(st.state_bytes) / static_cast<double>(st.observed_cells) : 0.0;
  return result;
}

}  // namespace glassmap::glass
