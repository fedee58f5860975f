#include "glassmap/glass/mapping.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>

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

namespace {

// The options with what only the classifiers read set to the defaults: equal keys, equal passes.
MappingOptions passKey(const MappingOptions& o) {
  MappingOptions k = o;
  k.max_memory_bytes = 0;
  k.heuristic = {};
  k.direct = o.method == Method::Direct ? sigmoidInputs(o.direct) : DirectOptions{};
  return k;
}

}  // namespace

struct BeamPasses::Data {
  const LaserLog* log = nullptr;
  std::size_t scans = 0;
  MappingOptions key;
  grid::HitMissGrid counts;
  std::optional<grid::AngleHistograms> hist;
  SigmoidSums sums;
  MappingStats stats;  // of the passes (counts, beams, their seconds)
  explicit Data(const grid::GridGeometry& g) : counts(g) {}
};

BeamPasses::BeamPasses() = default;
BeamPasses::~BeamPasses() = default;
BeamPasses::BeamPasses(BeamPasses&&) noexcept = default;
BeamPasses& BeamPasses::operator=(BeamPasses&&) noexcept = default;

MappingResult mapLog(const LaserLog& log, const MappingOptions& o,
                     const std::function<void(const char*, double)>& progress, BeamPasses* passes) {
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

  const MappingOptions key = passKey(o);
  std::unique_ptr<BeamPasses::Data> local;
  BeamPasses::Data* data = nullptr;
  if (passes && passes->data_ && passes->data_->log == &log && passes->data_->scans == log.scanCount() &&
      passes->data_->key == key) {
    data = passes->data_.get();
    ++passes->reused_;
    st = data->stats;
    st.seconds_counts = st.seconds_angles = 0.0;
  } else {
    if (passes) passes->data_.reset();  // the grid of an earlier log goes before this one's comes
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
    local = std::make_unique<BeamPasses::Data>(geometry);
    data = local.get();
    data->log = &log;
    data->scans = log.scanCount();
    data->key = key;
    const grid::IntegrationStats pass1 = grid::integrateCounts(log, o.beams, data->counts, report("counts"));
    st.scans = pass1.scans;
    st.beams = pass1.beams;
    st.hit_beams = pass1.hit_beams;
    st.cells_traversed = pass1.cells_traversed;
    st.seconds_counts = secondsSince(t0);

    t0 = std::chrono::steady_clock::now();
    data->hist.emplace(data->counts, bins);
    // No-return readings cross only what returned nothing their way (grid/no_returns.hpp); their
    // misses go into the standard occupancy map before the direct classifier reads d_real from it.
    grid::integrateNoReturns(log, o.beams, data->counts, *data->hist);
    if (o.method == Method::Direct) {
      data->sums =
          integrateSigmoid(log, o.beams, data->counts, o.occupancy, *data->hist, o.direct, nullptr, report("angles"));
    } else {
      grid::integrateAngles(log, o.beams, *data->hist, report("angles"));
    }
    st.seconds_angles = secondsSince(t0);
    data->stats = st;
  }
  const grid::HitMissGrid& counts = data->counts;
  const grid::AngleHistograms& hist = *data->hist;
  const SigmoidSums& sums = data->sums;

  auto t0 = std::chrono::steady_clock::now();
  result.evidence = o.method == Method::Heuristic ? classifyHeuristic(counts, hist, o.heuristic)
                                                  : classifyDirect(counts, hist, sums, o.direct, o.beams.miss_margin);
  // What a beam leaves in empty space, away from the surfaces' range noise and the panes' returns.
  const int clearance =
      static_cast<int>(std::ceil((o.beams.miss_margin + 3.0 * o.direct.range_sigma) / o.resolution)) + 1;
  st.empty = emptyHitRate(counts, result.evidence, clearance);
  st.p_hit_emp = o.direct.p_hit_emp;
  if (o.method == Method::Direct && o.direct.p_hit_emp_from_log && st.empty.hits + st.empty.misses > 0) {
    DirectOptions d = o.direct;
    d.p_hit_emp = st.empty.laplaceRate();
    result.evidence = classifyDirect(counts, hist, sums, d, o.beams.miss_margin);
    st.p_hit_emp = d.p_hit_emp;
  }
  st.seconds_classify = secondsSince(t0);

  st.observed_cells = counts.observedCells();
  st.candidate_cells = hist.size();
  st.glass_cells = result.evidence.countGlass();
  st.occupied_cells = result.evidence.countOccupied();
  st.state_bytes =
      counts.bytes() + hist.bytes() + (sums.log_occ.capacity() + sums.log_glass.capacity()) * sizeof(float);
  st.bytes_per_observed_cell =
      st.observed_cells ? static_cast<double>(st.state_bytes) / static_cast<double>(st.observed_cells) : 0.0;
  if (passes && local) passes->data_ = std::move(local);
  return result;
}

}  // namespace glassmap::glass
