#include "glassmap/pipeline/reports.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <utility>

#include "glassmap/core/atomic_file.hpp"
#include "glassmap/core/error.hpp"

namespace glassmap::pipeline {
namespace {

// The panes of the sparse-pane search: ends [m], returns, log10 NFA, transmission, coherence z and
// correlation, and the scans the coherence rests on.
nlohmann::json sparsePanesJson(const std::vector<glass::SparsePane>& panes) {
  nlohmann::json j = nlohmann::json::array();
  for (const glass::SparsePane& p : panes)
    j.push_back({{"a", {p.a.x(), p.a.y()}},
                 {"b", {p.b.x(), p.b.y()}},
                 {"returns", p.returns},
                 {"log10_nfa", p.log10_nfa},
                 {"transmission", p.transmission},
                 {"coherence_z", p.by_scan.z},
                 {"coherence_correlation", p.by_scan.correlation},
                 {"near_normal_scans", p.by_scan.scans},
                 {"visit_z", p.by_visit.z},
                 {"visit_correlation", p.by_visit.correlation},
                 {"visits", p.by_visit.scans},
                 {"place_z", p.by_place.z},
                 {"place_correlation", p.by_place.correlation},
                 {"place_pairs", p.by_place.scans}});
  return j;
}

// The profile's fitted numbers in the order profileJson lists them.
std::vector<std::pair<const char*, Estimate SensorProfile::*>> profileFields() {
  return {{"range_sigma_m", &SensorProfile::range_sigma_m},
          {"range_sigma_rel", &SensorProfile::range_sigma_rel},
          {"w_hit", &SensorProfile::w_hit},
          {"w_short", &SensorProfile::w_short},
          {"w_max", &SensorProfile::w_max},
          {"w_rand", &SensorProfile::w_rand},
          {"lambda_short", &SensorProfile::lambda_short},
          {"direct_peak", &SensorProfile::direct_peak},
          {"direct_sigma_deg", &SensorProfile::direct_sigma_deg},
          {"direct_floor", &SensorProfile::direct_floor},
          {"normal_lambda_per_deg", &SensorProfile::normal_lambda_per_deg},
          {"normal_floor", &SensorProfile::normal_floor},
          {"glass_offset_m", &SensorProfile::glass_offset_m}};
}

nlohmann::json binsJson(const std::vector<GlassAngleBin>& bins) {
  nlohmann::json out = nlohmann::json::array();
  for (const GlassAngleBin& b : bins) {
    if (b.beams == 0 && b.mirror_beams == 0) continue;
    out.push_back({{"theta_lo_deg", b.theta_lo},
                   {"theta_hi_deg", b.theta_hi},
                   {"beams", b.beams},
                   {"direct", b.direct},
                   {"mirror_beams", b.mirror_beams},
                   {"reflected", b.reflected}});
  }
  return out;
}

}  // namespace

void writeJsonFile(const std::filesystem::path& path, const nlohmann::json& j) {
  writeAtomically(path, [&](const std::filesystem::path& tmp) {
    std::ofstream out(tmp);
    out << j.dump(2) << "\n";
    out.close();  // a failed write shows only once the buffer is flushed
    if (!out) throw Error("cannot write", path.string());
  });
}

nlohmann::json profileJson(const SensorProfile& p) {
  nlohmann::json j = {{"source", p.source},
                      {"wall_beams", p.wall_beams},
                      {"glass_beams", p.glass_beams},
                      {"typical_range_m", p.typical_range_m},
                      {"fitted", nlohmann::json::array()}};
  for (const auto& [key, member] : profileFields()) {
    const Estimate& e = p.*member;
    j[key] = e.value;
    j[std::string(key) + "_se"] = e.se;
    if (e.fitted) j["fitted"].push_back(key);
  }
  return j;
}

SensorProfile profileFromJson(const nlohmann::json& j, const std::vector<std::string>& ignored) {
  if (!j.is_object()) throw Error("expected a mapping of sensor profile keys", {}, 0, "profile");
  SensorProfile p;
  const auto fields = profileFields();
  auto number = [](const std::string& key, const nlohmann::json& v) {
    if (!v.is_number()) throw Error("expected a number, got " + v.dump(), {}, 0, key);
    return v.get<double>();
  };
  auto count = [](const std::string& key, const nlohmann::json& v) {
    if (!v.is_number_unsigned() && !(v.is_number_integer() && v.get<long long>() >= 0))
      throw Error("expected a count, got " + v.dump(), {}, 0, key);
    return v.get<std::size_t>();
  };
  for (const auto& [key, v] : j.items()) {
    const auto field = std::find_if(fields.begin(), fields.end(), [&](const auto& f) {
      return key == f.first || key == std::string(f.first) + "_se";
    });
    if (field != fields.end()) {
      Estimate& e = p.*(field->second);
      (key == field->first ? e.value : e.se) = number(key, v);
    } else if (key == "source") {
      if (!v.is_string()) throw Error("expected text, got " + v.dump(), {}, 0, key);
      p.source = v.get<std::string>();
    } else if (key == "wall_beams") {
      p.wall_beams = count(key, v);
    } else if (key == "glass_beams") {
      p.glass_beams = count(key, v);
    } else if (key == "typical_range_m") {
      p.typical_range_m = std::max(0.0, number(key, v));
    } else if (key == "fitted") {
      if (!v.is_array()) throw Error("expected a list of keys, got " + v.dump(), {}, 0, key);
      for (const nlohmann::json& name : v) {
        const auto f = std::find_if(fields.begin(), fields.end(), [&](const auto& x) {
          return name.is_string() && name.get<std::string>() == x.first;
        });
        if (f == fields.end()) throw Error("not a fitted profile key: " + name.dump(), {}, 0, key);
        (p.*(f->second)).fitted = true;
      }
    } else if (std::find(ignored.begin(), ignored.end(), key) == ignored.end()) {
      throw Error("not a sensor profile key", {}, 0, key);
    }
  }
  return p;
}

nlohmann::json mapOptionsJson(const MapOptions& options) {
  const auto& o = options.mapping;
  const auto& d = o.direct;
  const auto& h = o.heuristic;
  return {{"method", toString(options.method)},
          {"resolution", o.resolution},
          {"angle_bin_deg", o.angle_bin_deg},
          {"range_cap", o.beams.range_cap},
          {"min_range", o.beams.min_range},
          {"clear_no_return", o.beams.clear_no_return},
          {"no_return_range", o.beams.no_return_range},
          {"no_returns", grid::toString(o.beams.no_return)},
          {"pane_grouping", options.vectorize.glass_voting ? "voting" : "regions"},
          {"miss_margin", o.beams.miss_margin},
          {"direct",
           {{"sigmoid_margin", d.sigmoid_margin},
            {"direct_sigma_deg", d.direct_sigma_deg},
            {"direct_peak", d.direct_peak},
            {"lobe_floor", d.lobe_floor},
            {"direct_floor", d.direct_floor},
            {"p_hit_occ", d.p_hit_occ},
            {"p_hit_emp", d.p_hit_emp},
            {"p_hit_emp_from_log", d.p_hit_emp_from_log},
            {"occ_hit_floor", d.occ_hit_floor},
            {"prior_glass", d.prior_glass},
            {"prior_occupied", d.prior_occupied},
            {"min_glass_hits", d.min_glass_hits},
            {"search_cells", d.search_cells}}},
          {"profile_lobe", options.profile_lobe},
          {"prune_unfitted_glass", options.prune_unfitted_glass},
          {"scan_fit",
           {{"enabled", options.scan_fit.enabled},
            {"reach", options.scan_fit.reach},
            {"max_range", options.scan_fit.max_range},
            {"band", options.scan_fit.band},
            {"tolerance", options.scan_fit.tolerance},
            {"min_gain", options.scan_fit.min_gain},
            {"min_returns", options.scan_fit.min_returns}}},
          {"scan_clutter",
           {{"enabled", options.scan_clutter.enabled},
            {"tolerance", options.scan_clutter.tolerance},
            {"max_range", options.scan_clutter.max_range},
            {"min_share", options.scan_clutter.min_share},
            {"max_gap", options.scan_clutter.max_gap},
            {"max_free", options.scan_clutter.max_free}}},
          {"sparse_panes",
           {{"enabled", options.sparse_panes},
            {"angle_tol_deg", options.sparse.angle_tol_deg},
            {"offset_tol", options.sparse.offset_tol},
            {"range_sigma", options.sparse.range_sigma},
            {"min_transmission", options.sparse.min_transmission},
            {"min_normal_rate", options.sparse.min_normal_rate},
            {"min_lobe_contrast", options.sparse.min_lobe_contrast},
            {"min_specific", options.sparse.min_specific},
            {"max_place_dt_s", options.sparse.max_place_dt_s},
            {"max_place_ds", options.sparse.max_place_ds},
            {"log10_max_nfa", options.sparse.log10_max_nfa}}},
          {"opaque_glass",
           {{"enabled", options.opaque_glass},
            {"beyond", options.opaque.beyond},
            {"min_transmission", options.opaque.min_transmission},
            {"min_crossings", options.opaque.min_crossings},
            {"min_unpassed_returns", options.opaque.min_unpassed_returns},
            {"max_transient_p", options.opaque.max_transient_p},
            {"min_transient_correlation", options.opaque.min_transient_correlation},
            {"min_visit_correlation", options.opaque.min_visit_correlation},
            {"max_visit_gap_s", options.opaque.max_visit_gap_s}}},
          {"phantoms",
           {{"enabled", options.phantoms},
            {"glass_margin", options.phantom.glass_margin},
            {"block_margin", options.phantom.block_margin},
            {"min_folded_fraction", options.phantom.min_folded_fraction}}},
          {"mrf",
           {{"solver", mrf::toString(options.mrf.solver)},
            {"psi", mrf::toString(options.mrf.psi)},
            {"unary_weight", options.mrf.unary_weight},
            {"unseen_glass_neutral", options.mrf.unseen_glass_neutral},
            {"tile", options.mrf.tile},
            {"sweeps", options.mrf.sweeps}}},
          {"heuristic",
           {{"min_hits", h.min_hits},
            {"min_window_hit_ratio", h.min_window_hit_ratio},
            {"min_other_misses", h.min_other_misses},
            {"max_other_hit_ratio", h.max_other_hit_ratio},
            {"occupied_hit_ratio", h.occupied_hit_ratio}}}};
}

std::uint64_t logOnDiskBytes(const LaserLog& log) { return log.spooled ? log.spooled->spool->bytesOnDisk() : 0; }

nlohmann::json mapStatsJson(const MapResult& result, const MapOptions& options, const MapRunInfo& run) {
  const glass::CellEvidence& e = result.evidence;
  const vector::VectorizeResult& floorplan = result.floorplan;
  const mrf::RefineResult& refined = result.mrf;
  const glass::PhantomStats& phantom = result.phantoms;
  const auto& st = result.stats;
  nlohmann::json j = {{"log", run.log},
                      {"log_on_disk_bytes", run.log_on_disk_bytes},
                      {"scans", st.scans},
                      {"beams", st.beams},
                      {"hit_beams", st.hit_beams},
                      {"cells_traversed", st.cells_traversed},
                      {"grid",
                       {{"width", e.geometry.width},
                        {"height", e.geometry.height},
                        {"resolution", e.geometry.resolution},
                        {"origin", {e.geometry.origin.x(), e.geometry.origin.y()}}}},
                      {"observed_cells", st.observed_cells},
                      {"candidate_cells", st.candidate_cells},
                      {"glass_cells", st.glass_cells},
                      {"occupied_cells", st.occupied_cells},
                      {"state_bytes", st.state_bytes},
                      {"bytes_per_observed_cell", st.bytes_per_observed_cell},
                      {"empty_space",
                       {{"hits", st.empty.hits},
                        {"misses", st.empty.misses},
                        {"cells", st.empty.cells},
                        {"hit_rate", st.empty.rate()},
                        {"p_hit_emp", st.p_hit_emp}}},
                      {"seconds",
                       {{"read", run.seconds_read},
                        {"counts", st.seconds_counts},
                        {"angles", st.seconds_angles},
                        {"classify", st.seconds_classify},
                        {"mrf", refined.seconds},
                        {"sparse_panes", result.seconds.sparse},
                        {"opaque_glass", result.seconds.opaque},
                        {"phantoms", result.seconds.phantoms},
                        {"vectorize", floorplan.stats.seconds},
                        {"scan_fit", result.seconds.scan_fit},
                        {"scan_clutter", result.seconds.scan_clutter},
                        {"calibration", result.seconds.calibration},
                        {"total", run.seconds_total}}},
                      {"sensor", profileJson(result.profile)},
                      {"calibrated", result.calibrated},
                      {"passes", result.passes},
                      {"reused_beam_walks", result.reused_beam_walks},
                      {"calibration_warnings", result.calibration.warnings},
                      {"mrf_changed_cells", refined.changed},
                      {"mrf_energy", {{"before", refined.energy_before}, {"after", refined.energy_after}}},
                      {"sparse_panes",
                       {{"weak_returns", result.sparse.weak_returns},
                        {"runs_tested", result.sparse.runs_tested},
                        {"panes", result.sparse.panes},
                        {"metres", result.sparse.metres},
                        {"cells_labelled", result.sparse.cells_labelled},
                        {"rejected_chance", result.sparse.rejected_chance},
                        {"rejected_opaque", result.sparse.rejected_opaque},
                        {"rejected_faint", result.sparse.rejected_faint},
                        {"rejected_unspecific", result.sparse.rejected_unspecific},
                        {"rejected_transient", result.sparse.rejected_transient},
                        {"rejected_transient_one_visit", result.sparse.rejected_transient_one_visit},
                        {"rejected_one_visit", result.sparse.rejected_one_visit},
                        {"rejected_place", result.sparse.rejected_place},
                        {"rejected_through", result.sparse.rejected_through},
                        {"rejected_duplicate", result.sparse.rejected_duplicate},
                        {"found", sparsePanesJson(result.sparse.found)}}},
                      {"opaque_glass",
                       {{"glass_cells", result.opaque.glass_cells},
                        {"decided", result.opaque.decided},
                        {"decided_by_pane", result.opaque.decided_by_pane},
                        {"spurious_share", result.opaque.spuriousShare()},
                        {"relabelled", result.opaque.relabelled},
                        {"mirror_images", result.opaque.images},
                        {"through_glass_only", result.opaque.through_glass_only},
                        {"panes_tested", result.opaque.panes_tested},
                        {"transient_panes", result.opaque.transient_panes},
                        {"transient_cells", result.opaque.transient_cells}}},
                      {"mirror_phantoms",
                       {{"beams_through_glass", phantom.beams_through_glass},
                        {"folded_beams", phantom.folded_beams},
                        {"cells_cleared", phantom.cells_cleared}}},
                      {"glass_cells_off_segments", result.pruned_glass},
                      {"cells_filled_on_panes", result.filled_glass},
                      {"scan_fit", scanFitJson(result.scan_fit)},
                      {"scan_clutter", scanClutterJson(result.scan_clutter)},
                      {"glass_segments", floorplan.map.count(Material::Glass)},
                      {"wall_segments", floorplan.map.count(Material::Wall)},
                      {"peak_memory_bytes", run.peak_memory_bytes},
                      {"options", mapOptionsJson(options)}};
  for (const std::string& f : run.files) j["files"].push_back(f);
  return j;
}

std::size_t gridMemoryBudget(std::size_t budget_bytes, const LaserLog& log) {
  return budget_bytes > log.memoryBytes() ? budget_bytes - log.memoryBytes() : 1;
}

std::size_t peakMemoryBytes() {
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  return static_cast<std::size_t>(usage.ru_maxrss) * 1024;  // Linux reports KiB
}

nlohmann::json sensorParamsJson(const sensor::SensorParams& p) {
  const double sum = p.z_hit + p.z_short + p.z_max + p.z_rand;
  return {{"sigma_hit_m", p.sigma_hit},
          {"sigma_hit_rel", p.sigma_hit_rel},
          {"w_hit", p.z_hit / sum},
          {"w_short", p.z_short / sum},
          {"w_max", p.z_max / sum},
          {"w_rand", p.z_rand / sum},
          {"lambda_short", p.lambda_short},
          {"direct_peak", p.direct_peak},
          {"direct_sigma_deg", p.direct_sigma_deg},
          {"direct_floor", p.direct_floor},
          {"normal_lambda_per_deg", p.lambda_normal},
          {"normal_floor", p.normal_floor}};
}

nlohmann::json scanClutterJson(const vector::ScanClutterStats& s) {
  return {{"returns", s.returns},
          {"unexplained", s.unexplained},
          {"replaced", s.replaced},
          {"added", s.added},
          {"restored", s.restored},
          {"explained_before", s.explained_before},
          {"explained_walls", s.explained_walls},
          {"explained_after", s.explained_after},
          {"candidates", s.candidates}};
}

nlohmann::json scanFitJson(const vector::ScanFitStats& s) {
  return {{"returns", s.returns},
          {"segments", s.segments},
          {"moved", s.moved},
          {"mean_shift", s.mean_shift},
          {"band", s.band},
          {"explained_before", s.explained_before},
          {"explained_after", s.explained_after},
          {"junctions", s.junctions}};
}

nlohmann::json localizeSummaryJson(const LocalizeResult& result, const LocalizeOptions& options) {
  const localize::LocalizeResult& r = result.run;
  nlohmann::json calibrations = nlohmann::json::array();
  for (const localize::SelfCalibrationFit& f : r.calibrations)
    calibrations.push_back({{"time_s", f.time},
                            {"scans", f.scans},
                            {"trusted_m", f.trusted_m},
                            {"applied", f.applied},
                            {"motion_windows", f.motion_windows},
                            {"odometry_walk_trans_m2_per_m", f.noise.walk_trans},
                            {"odometry_walk_heading_rad2_per_m", f.noise.walk_heading},
                            {"params", sensorParamsJson(f.params)}});
  return {{"model", result.model},
          {"glass_as", sensor::toString(options.sensor.glass_as)},
          {"scans", r.scans},
          {"updates", r.updates},
          {"resamplings", r.resamplings},
          {"injected_particles", r.injected},
          {"relocalizations", r.relocalizations},
          {"probes", r.probes},
          {"breaks", r.breaks},
          {"converged", r.converged},
          {"converged_at_s", r.converged ? nlohmann::json(r.converged_at) : nlohmann::json(nullptr)},
          {"mean_particles", r.mean_particles},
          {"beams", options.filter.beams},
          {"seconds", r.seconds},
          {"ms_per_update", 1e3 * r.seconds_per_update},
          {"log_seconds", r.log_duration},
          {"real_time_factor", r.realTimeFactor()},
          {"seed", options.filter.filter.seed},
          {"sensor_params", sensorParamsJson(r.final_params)},
          {"self_calibration", calibrations}};
}

std::string calibrationSource(const std::string& log_path, const std::string& plan_path) {
  namespace fs = std::filesystem;
  return "calibrated from " + fs::path(log_path).filename().string() +
         (plan_path.empty() ? " against its own map" : " against " + fs::path(plan_path).filename().string());
}

nlohmann::json calibrationJson(const SensorProfile& profile, const CalibrateLogResult& r, const std::string& log_path,
                               const std::string& plan_path, double seconds) {
  nlohmann::json j = profileJson(profile);
  j["log"] = log_path;
  j["floorplan"] = plan_path.empty() ? nlohmann::json(nullptr) : nlohmann::json(plan_path);
  j["own_floorplan"] = r.own_floorplan;
  j["floorplan_walls"] = r.floorplan_walls;
  j["floorplan_panes"] = r.floorplan_panes;
  j["rounds"] = r.rounds;
  j["scans_used"] = r.fit.scans;
  j["aligned_scans"] = r.fit.aligned_scans;
  j["median_alignment_m"] = r.fit.median_alignment_m;
  j["median_alignment_deg"] = r.fit.median_alignment_deg;
  j["refracted_beams"] = r.fit.refracted_beams;
  j["transient_panes"] = r.fit.transient_panes;
  j["transient_length_m"] = r.fit.transient_length_m;
  j["range_sigma_walls_m"] = r.fit.range_sigma_em_m;
  j["range_sigma_in_scan_m"] = r.fit.range_sigma_local_m;
  j["angle_bins"] = binsJson(r.fit.bins);
  j["warnings"] = r.fit.warnings;
  j["seconds"] = seconds;
  return j;
}

}  // namespace glassmap::pipeline
