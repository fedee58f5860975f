#include "glassmap/pipeline/map_log.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>

#include "glassmap/core/error.hpp"
#include "glassmap/vector/from_evidence.hpp"
#include "local_frame.hpp"

namespace glassmap::pipeline {
namespace {

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The re-centring offset of a log: from the extent of its laser poses (local_frame.hpp).
Vec2 localOffset(const LaserLog& log) {
  Eigen::AlignedBox2d box;
  forEachScanBlock(log, [&](std::span<const LaserScan> block, std::size_t) {
    for (const LaserScan& s : block)
      if (s.laser_pose.t.allFinite()) box.extend(s.laser_pose.t);
  });
  return detail::recentringOffset(box);
}

// A log re-centred on its poses (see localOffset), or the log itself. The scans are shifted as
// the passes read them, a block at a time (no second copy of the log, in memory or on disk).
struct LocalLog {
  Vec2 offset;
  LaserLog shifted;
  const LaserLog* log;
  explicit LocalLog(const LaserLog& input) : offset(localOffset(input)), log(&input) {
    if (offset.isZero()) return;
    shifted.spooled = input.spooled.value_or(SpooledScans{});
    if (!input.spooled) shifted.spooled->spool = borrowScans(input.scans);
    shifted.spooled->shift += offset;
    log = &shifted;
  }
};

// One pass of the chain over a log already in its local frame; with `passes`, the passes over the
// beams of an earlier call with the same beam settings are reused (glass::BeamPasses).
MapResult mapOnce(const LaserLog& log, const MapOptions& options, const Progress& progress,
                  glass::BeamPasses* passes = nullptr) {
  const auto t0 = std::chrono::steady_clock::now();
  auto report = [&](const char* stage, double f) {
    if (progress) progress(stage, f);
  };
  MapResult out;

  // Cell classifier (paper 2.5.3 heuristic, 2.5.4 direct reflection); the MRF refines Direct's
  // evidence.
  glass::MappingOptions mapping = options.mapping;
  mapping.method = options.method == MapMethod::Heuristic ? glass::Method::Heuristic : glass::Method::Direct;
  glass::MappingResult classified = glass::mapLog(log, mapping, progress, passes);
  out.evidence = std::move(classified.evidence);
  out.stats = classified.stats;
  out.seconds.counts = out.stats.seconds_counts;
  out.seconds.angles = out.stats.seconds_angles;
  out.seconds.classify = out.stats.seconds_classify;

  // MRF over the grid (paper 2.5.5).
  if (options.method == MapMethod::Mrf) {
    report("mrf", 0.0);
    out.mrf = mrf::refine(out.evidence, options.mrf);
    out.seconds.mrf = out.mrf.seconds;
    report("mrf", 1.0);
  }

  // A cell step between the MRF and the floorplan: reported to progress as `stage`, timed into
  // `seconds`.
  auto step = [&](bool enabled, const char* stage, double& seconds, auto&& run) {
    if (!enabled) return;
    report(stage, 0.0);
    const auto ts = std::chrono::steady_clock::now();
    run();
    seconds = secondsSince(ts);
    report(stage, 1.0);
  };
  // Panes too faint for the cell classifiers: weak returns lined up along their normals.
  step(options.sparse_panes, "sparse", out.seconds.sparse,
       [&] { out.sparse = glass::findSparsePanes(log, mapping.beams, options.sparse, out.evidence); });
  // Glass is crossed: glass cells whose crossing beams stop just behind them are something's front.
  step(options.opaque_glass, "opaque", out.seconds.opaque,
       [&] { out.opaque = glass::relabelOpaqueGlass(log, mapping.beams, options.opaque, out.evidence); });
  // Mirror phantoms: cells drawn by beams a pane folded.
  step(options.phantoms, "phantoms", out.seconds.phantoms,
       [&] { out.phantoms = glass::suppressMirrorPhantoms(log, mapping.beams, options.phantom, out.evidence); });

  // Vector floorplan, then the pane fit of the cells against it.
  if (options.fit_floorplan || options.prune_unfitted_glass) {
    report("vectorize", 0.0);
    out.floorplan = vector::vectorize(vector::toLabelGrid(out.evidence), options.vectorize);
    out.has_floorplan = true;
    out.seconds.vectorize = out.floorplan.stats.seconds;
    report("vectorize", 1.0);
    // The walls where the returns put them (the cells draw them up to half a cell off).
    step(options.scan_fit.enabled, "scan fit", out.seconds.scan_fit,
         [&] { out.scan_fit = vector::fitToScans(out.floorplan, log, mapping.beams, options.scan_fit); });
  }
  if (options.prune_unfitted_glass) {
    out.pruned_glass = vector::pruneUnfittedGlass(out.evidence, out.floorplan.map, options.prune_tolerance);
    out.filled_glass = vector::fillFittedGlass(out.evidence, out.floorplan.map);
  }

  // The later steps relabel cells: count what comes out.
  out.stats.glass_cells = out.evidence.countGlass();
  out.stats.occupied_cells = out.evidence.countOccupied();
  out.seconds.total = secondsSince(t0);
  return out;
}

// Every surface of a pass's floorplan the laser sees: its walls and glass and its clutter layer.
VectorMap surfacesOf(const vector::VectorizeResult& floorplan) {
  VectorMap all = floorplan.map;
  all.segments.insert(all.segments.end(), floorplan.extras.clutter.segments.begin(),
                      floorplan.extras.clutter.segments.end());
  return all;
}

// Fits the profile against a pass's floorplan; false (the reason in fit.warnings) when it has no wall.
// With noise_in_prior, the prior's range noise is the log's in-scan estimate (inScanNoise), which
// the fit would make again from the same scans: it is taken as it is.
bool fitProfile(const LaserLog& log, const VectorMap& plan, const MapOptions& options, const SensorProfile& prior,
                sensor::CalibrationResult& fit, bool noise_in_prior = false) {
  if (std::none_of(plan.segments.begin(), plan.segments.end(),
                   [](const MapSegment& s) { return s.material == Material::Wall; })) {
    fit = {};
    fit.profile = prior;
    fit.warnings.push_back("the first pass found no wall to calibrate against: default sensor profile kept");
    return false;
  }
  sensor::CalibrationOptions c = options.calibration;
  c.prior = prior;
  // The plan was mapped from this very log.
  c.sigma_source = noise_in_prior ? sensor::SigmaSource::Prior : sensor::SigmaSource::Local;
  fit = sensor::calibrate(log, plan, c);
  return true;
}

// The first pass left too few beams on glass to fit the lobe: a pass with the broad search lobe
// (and the fitted range noise), and the fit against its floorplan when that one has the beams.
void searchLobe(const LaserLog& log, const MapOptions& options, const SensorProfile& prior, bool noise_in_prior,
                const Progress& progress, glass::BeamPasses& walks, sensor::CalibrationResult& fit) {
  SensorProfile broad = fit.profile;
  broad.direct_peak = {options.search_peak};
  broad.direct_sigma_deg = {options.search_sigma_deg};
  broad.direct_floor = {options.search_floor};
  MapOptions wide = options;
  wide.fit_floorplan = true;
  applyProfile(wide, broad);
  const MapResult look = mapOnce(log, wide, progress, &walks);
  char lobe[96];
  std::snprintf(lobe, sizeof lobe, "a pass with a broad lobe (peak %.2g, sigma %.3g deg, floor %.2g)",
                options.search_peak, options.search_sigma_deg, options.search_floor);
  sensor::CalibrationResult refit;
  if (fitProfile(log, surfacesOf(look.floorplan), options, prior, refit, noise_in_prior) &&
      refit.profile.direct_sigma_deg.fitted) {
    // What the first pass's fit said, then the search's.
    std::vector<std::string> said;
    for (const std::string& w : fit.warnings) said.push_back("first pass: " + w);
    said.push_back("too few beams on glass to fit the lobe after the first pass: fitted against " + std::string(lobe) +
                   ", " + std::to_string(refit.profile.glass_beams) + " beams on its glass");
    refit.warnings.insert(refit.warnings.begin(), said.begin(), said.end());
    fit = std::move(refit);
  } else {
    fit.warnings.push_back(std::string(lobe) + " found no more glass to fit the lobe against");
  }
}

// A refitted lobe within one standard error of the last in peak, sigma and floor (a lobe that is
// not fitted is settled where it was).
bool lobeSettled(const SensorProfile& last, const SensorProfile& refit) {
  if (!refit.direct_sigma_deg.fitted) return true;
  const auto near = [](const Estimate& a, const Estimate& b) { return std::abs(a.value - b.value) <= b.se; };
  return last.direct_sigma_deg.fitted && near(last.direct_peak, refit.direct_peak) &&
         near(last.direct_sigma_deg, refit.direct_sigma_deg) && near(last.direct_floor, refit.direct_floor);
}

// The lobe a pass mapped with (its classifier's) agrees with a fit of the lobe against that pass's
// floorplan: peak and sigma each within one standard error of the fit, and the floor too, or both
// floors at or below the spurious rate p_hit_emp. The classifier explains a hit off the lobe by
// the larger of the floor's rate and the spurious rate, so floors below it change a cell's
// likelihood only in the lobe's flanks, by less than the spurious rate does.
bool lobeAgrees(const glass::DirectOptions& used, const SensorProfile& fit) {
  if (!fit.direct_sigma_deg.fitted) return true;
  const auto near = [](double a, const Estimate& b) { return std::abs(a - b.value) <= b.se; };
  const bool floors = near(used.direct_floor, fit.direct_floor) ||
                      std::max(used.direct_floor, fit.direct_floor.value) <= used.p_hit_emp;
  return near(used.direct_peak, fit.direct_peak) && near(used.direct_sigma_deg, fit.direct_sigma_deg) && floors;
}

// The fields applyProfile sets are equal.
bool sameThresholds(const MapOptions& a, const MapOptions& b) {
  const glass::DirectOptions &x = a.mapping.direct, &y = b.mapping.direct;
  return x.direct_sigma_deg == y.direct_sigma_deg && x.direct_peak == y.direct_peak &&
         x.direct_floor == y.direct_floor && x.sigmoid_margin == y.sigmoid_margin && x.range_sigma == y.range_sigma &&
         a.mapping.beams.miss_margin == b.mapping.beams.miss_margin &&
         a.phantom.glass_margin == b.phantom.glass_margin && a.phantom.block_margin == b.phantom.block_margin &&
         a.vectorize.noise_floor == b.vectorize.noise_floor &&
         a.vectorize.glass.max_distance == b.vectorize.glass.max_distance &&
         a.vectorize.wall.max_distance == b.vectorize.wall.max_distance && a.scan_fit.band == b.scan_fit.band &&
         a.scan_fit.reach == b.scan_fit.reach;
}

void countSegments(const VectorMap& plan, std::size_t& walls, std::size_t& panes) {
  for (const MapSegment& s : plan.segments) ++(s.material == Material::Wall ? walls : panes);
}

}  // namespace

bool keepPlausibleLobe(const MapOptions& options, const SensorProfile& prior, sensor::CalibrationResult& fit) {
  SensorProfile& p = fit.profile;
  if (!p.direct_sigma_deg.fitted) return true;
  const double sigma = p.direct_sigma_deg.value;
  const bool wide = sigma - 2.0 * p.direct_sigma_deg.se > options.max_lobe_sigma_deg &&
                    sigma > options.max_lobe_sigma_deg * (1.0 + options.max_lobe_sigma_bias);
  const bool faint = p.direct_peak.value + 2.0 * p.direct_peak.se < options.min_lobe_peak;
  // A peak within two standard errors of none: the fit cannot tell a lobe from no direct returns.
  const bool unknown = p.direct_peak.value < 2.0 * p.direct_peak.se;
  if (!wide && !faint && !unknown) return true;
  char why[80];
  if (wide)
    std::snprintf(why, sizeof why, "wider than glass shows (at most %.0f deg)", options.max_lobe_sigma_deg);
  else if (faint)
    std::snprintf(why, sizeof why, "fainter than glass shows (a peak of at least %.2f)", options.min_lobe_peak);
  else
    std::snprintf(why, sizeof why, "not told apart from no direct returns (a peak under 2 standard errors)");
  char what[320];
  std::snprintf(what, sizeof what,
                "the fitted glass lobe (peak %.3f +- %.3f, sigma %.1f +- %.1f deg) is %s: what the first pass took "
                "for panes is likely not glass; the map keeps the prior lobe",
                p.direct_peak.value, p.direct_peak.se, p.direct_sigma_deg.value, p.direct_sigma_deg.se, why);
  fit.warnings.push_back(what);
  p.direct_peak = prior.direct_peak;
  p.direct_sigma_deg = prior.direct_sigma_deg;
  p.direct_floor = prior.direct_floor;
  return false;
}

const char* toString(MapMethod method) {
  switch (method) {
    case MapMethod::Heuristic: return "heuristic";
    case MapMethod::Direct: return "direct";
    case MapMethod::Mrf: return "mrf";
  }
  return "?";
}

MapMethod parseMapMethod(const std::string& name) {
  for (MapMethod m : {MapMethod::Heuristic, MapMethod::Direct, MapMethod::Mrf})
    if (name == toString(m)) return m;
  throw Error("unknown mapping method '" + name + "' (expected heuristic, direct or mrf)", {}, 0, "method");
}

bool applyProfile(MapOptions& o, const SensorProfile& p) {
  const MapOptions defaults;
  const double res = o.mapping.resolution;
  const double sigma = typicalRangeSigma(p);  // the noise at the ranges the log's returns have
  // A value the caller changed from its default is kept; a default follows the profile.
  bool changed = false;
  auto set = [&changed](double& field, double default_value, double from_profile) {
    if (field != default_value || field == from_profile) return;
    field = from_profile;
    changed = true;
  };
  const glass::DirectOptions& dd = defaults.mapping.direct;
  glass::DirectOptions& d = o.mapping.direct;
  if (o.profile_lobe) {
    // Rounded far below the fit's standard errors (about 0.01 in the peak, 0.1 deg in sigma): the
    // fit's last digits follow the float rounding of the log's coordinates, and a cell on the
    // edge of two labels must not (the same log anywhere in the world maps to the same cells).
    auto round_to = [](double x, double step) { return step * std::round(x / step); };
    set(d.direct_sigma_deg, dd.direct_sigma_deg, std::max(0.1, round_to(p.direct_sigma_deg.value, 1e-3)));
    set(d.direct_peak, dd.direct_peak, std::clamp(round_to(p.direct_peak.value, 1e-4), o.min_lobe_peak, 0.999));
    set(d.direct_floor, dd.direct_floor, std::clamp(round_to(p.direct_floor.value, 1e-5), 0.0, 0.5));
  }
  // Range noise: a pane's returns spread over the cells about it (PaneLanding), and a reading
  // lands within 3 sigma of its surface.
  set(d.range_sigma, dd.range_sigma, sigma);
  set(d.sigmoid_margin, dd.sigmoid_margin, std::max(dd.sigmoid_margin, 3.0 * sigma / res));
  set(o.mapping.beams.miss_margin, defaults.mapping.beams.miss_margin,
      std::max(defaults.mapping.beams.miss_margin, 3.0 * sigma));
  set(o.sparse.range_sigma, defaults.sparse.range_sigma, sigma);
  set(o.sparse.range_sigma_rel, defaults.sparse.range_sigma_rel, p.range_sigma_rel.value);
  set(o.opaque.range_sigma, defaults.opaque.range_sigma, sigma);
  set(o.opaque.range_sigma_rel, defaults.opaque.range_sigma_rel, p.range_sigma_rel.value);
  set(o.phantom.glass_margin, defaults.phantom.glass_margin, std::max(defaults.phantom.glass_margin, 3.0 * sigma));
  set(o.phantom.block_margin, defaults.phantom.block_margin, std::max(defaults.phantom.block_margin, 6.0 * sigma));
  set(o.vectorize.noise_floor, defaults.vectorize.noise_floor, std::max(defaults.vectorize.noise_floor, sigma / res));
  set(o.vectorize.glass.max_distance, defaults.vectorize.glass.max_distance,
      std::max(defaults.vectorize.glass.max_distance, 1.5 * sigma));
  set(o.vectorize.wall.max_distance, defaults.vectorize.wall.max_distance,
      std::max(defaults.vectorize.wall.max_distance, 2.5 * sigma));
  // The walls onto the returns: a wall's returns within 2 sigma of its band's centre, and as far
  // to move as with a precise laser beyond it.
  set(o.scan_fit.band, defaults.scan_fit.band, std::max(defaults.scan_fit.band, 2.0 * sigma));
  set(o.scan_fit.reach, defaults.scan_fit.reach,
      std::max(defaults.scan_fit.reach, o.scan_fit.band + defaults.scan_fit.reach - defaults.scan_fit.band));
  return changed;
}

MapResult mapLog(const LaserLog& input, const MapOptions& options, const Progress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  const LocalLog local(input);
  const LaserLog& log = *local.log;
  MapResult out;
  const bool calibrating = !options.sensor && options.calibrate && options.calibration_rounds > 0;
  if (options.sensor) {
    MapOptions o = options;
    applyProfile(o, *options.sensor);
    out = mapOnce(log, o, progress);
    out.profile = *options.sensor;
  } else if (calibrating) {
    // The range noise needs no map (neighbouring readings within scans): the first pass has it
    // already, and the fit against its floorplan gives the same (SigmaSource::Local), so that a log
    // whose lobe keeps the prior's is mapped once.
    SensorProfile profile;
    MapOptions first = options;
    const bool noise = sensor::inScanNoise(log, options.calibration, profile);
    if (noise) applyProfile(first, profile);
    first.fit_floorplan = true;
    // Later passes differ in the lobe only (the noise came first): they reuse this one's walks
    // over the beams when its thresholds are theirs.
    glass::BeamPasses walks;
    MapResult pass = mapOnce(log, first, progress, &walks);
    MapOptions last = first;  // the options of `pass`
    int passes = 1;
    sensor::CalibrationResult fit;
    for (int round = 0; round < options.calibration_rounds; ++round) {
      if (progress) progress("calibrate", 0.0);
      sensor::CalibrationResult next;
      // The noise of `profile` is the in-scan estimate in every round (the fits keep it).
      if (!fitProfile(log, surfacesOf(pass.floorplan), options, profile, next, noise)) {
        if (round == 0) fit = std::move(next);
        break;
      }
      if (round == 0 && options.lobe_search && options.profile_lobe && !next.profile.direct_sigma_deg.fitted)
        searchLobe(log, options, profile, noise, progress, walks, next);
      keepPlausibleLobe(options, profile, next);
      if (progress) progress("calibrate", 1.0);
      // The lobe fitted against a map made with the last fit's within its standard errors of it:
      // that map is the one (the fit and the map agree).
      if (round > 0 && lobeSettled(profile, next.profile)) break;
      fit = std::move(next);
      out.calibrated = true;
      profile = fit.profile;
      profile.source = "calibrated from the log";
      MapOptions o = options;
      applyProfile(o, profile);
      o.fit_floorplan = first.fit_floorplan;
      // A profile that sets the very thresholds the last pass used would map the same labels.
      if (sameThresholds(o, last)) break;
      // One whose lobe agrees with the first pass's within the fit's errors, and that sets its
      // other thresholds, would map them within those errors: the first pass is the map, and the
      // profile keeps its lobe (so that the profile maps the map again). A laser with the default
      // lobe is mapped once.
      if (round == 0 && lobeAgrees(last.mapping.direct, profile)) {
        const glass::DirectOptions& used = last.mapping.direct;
        SensorProfile kept = profile;
        kept.direct_peak = {used.direct_peak};
        kept.direct_sigma_deg = {used.direct_sigma_deg};
        kept.direct_floor = {used.direct_floor};
        MapOptions same_lobe = options;
        applyProfile(same_lobe, kept);
        same_lobe.fit_floorplan = first.fit_floorplan;
        if (sameThresholds(same_lobe, last)) {
          char what[320];
          std::snprintf(what, sizeof what,
                        "the fitted glass lobe (peak %.3f +- %.3f, sigma %.2f +- %.2f deg, floor %.4f +- %.4f) agrees "
                        "with the first pass's (%.3g, %.3g deg, %.3g): the map and the profile keep that lobe",
                        profile.direct_peak.value, profile.direct_peak.se, profile.direct_sigma_deg.value,
                        profile.direct_sigma_deg.se, profile.direct_floor.value, profile.direct_floor.se,
                        used.direct_peak, used.direct_sigma_deg, used.direct_floor);
          fit.warnings.push_back(what);
          profile = kept;
          break;
        }
      }
      pass = mapOnce(log, o, progress, &walks);
      last = o;
      ++passes;
    }
    const bool calibrated = out.calibrated;
    out = std::move(pass);
    out.passes = passes;
    out.reused_beam_walks = walks.reused();
    // The first pass fitted a floorplan to calibrate against; the caller asked for none.
    if (!options.fit_floorplan && !options.prune_unfitted_glass) {
      out.floorplan = {};
      out.has_floorplan = false;
      out.seconds.vectorize = 0.0;
      out.seconds.scan_fit = 0.0;
      out.scan_fit = {};
    }
    out.calibrated = calibrated;
    out.profile = profile;
    out.calibration = std::move(fit);
  } else {
    out = mapOnce(log, options, progress);
  }

  // The clutter layer that explains the returns the building leaves (once, on the final plan).
  if (out.has_floorplan && options.fit_floorplan && options.scan_clutter.enabled) {
    if (progress) progress("scan clutter", 0.0);
    const vector::LabelGrid labels = vector::toLabelGrid(out.evidence);
    out.scan_clutter =
        vector::clutterFromScans(out.floorplan, log, options.mapping.beams, &labels, {}, options.scan_clutter);
    out.seconds.scan_clutter = out.scan_clutter.seconds;
    if (progress) progress("scan clutter", 1.0);
  }

  // Back to the log's frame.
  if (!local.offset.isZero()) {
    out.evidence.geometry.origin += local.offset;
    for (VectorMap* m : {&out.floorplan.map, &out.floorplan.extras.clutter})
      for (MapSegment& seg : m->segments) {
        seg.a += local.offset;
        seg.b += local.offset;
      }
    for (DoorOpening& d : out.floorplan.extras.doors) d.a += local.offset, d.b += local.offset;
    for (glass::SparsePane& p : out.sparse.found) p.a += local.offset, p.b += local.offset;
    for (RoomPolygon& r : out.floorplan.extras.rooms)
      for (Vec2& p : r.ring) p += local.offset;
  }
  const double last_pass = out.seconds.total;
  out.seconds.total = secondsSince(t0);
  if (calibrating) out.seconds.calibration = out.seconds.total - last_pass - out.seconds.scan_clutter;
  return out;
}

CalibrateLogResult calibrateLog(const LaserLog& input, const VectorMap* floorplan, const MapOptions& options,
                                const Progress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  CalibrateLogResult out;
  if (floorplan) {
    out.fit = sensor::calibrate(input, *floorplan, options.calibration);
    out.rounds = 1;
    countSegments(*floorplan, out.floorplan_walls, out.floorplan_panes);
  } else {
    MapOptions o = options;
    o.sensor.reset();
    o.calibrate = true;
    o.calibration_rounds = std::max(1, options.calibration_rounds);
    const MapResult map = mapLog(input, o, progress);
    if (!map.calibrated)
      throw Error("cannot calibrate: " +
                  (map.calibration.warnings.empty() ? std::string("no wall") : map.calibration.warnings.front()));
    // The profile the final pass used, refitted once more against that pass's floorplan.
    const LocalLog local(input);
    VectorMap plan = surfacesOf(map.floorplan);
    for (MapSegment& s : plan.segments) {
      s.a -= local.offset;
      s.b -= local.offset;
    }
    if (progress) progress("calibrate", 0.0);
    if (!fitProfile(*local.log, plan, o, map.profile, out.fit))
      throw Error("cannot calibrate: the map of the log has no wall");
    if (progress) progress("calibrate", 1.0);
    out.own_floorplan = true;
    out.rounds = map.passes;
    countSegments(plan, out.floorplan_walls, out.floorplan_panes);
  }
  out.seconds = secondsSince(t0);
  return out;
}

}  // namespace glassmap::pipeline
