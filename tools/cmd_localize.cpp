// glassmap localize --map FLOORPLAN LOG -o EST.tum: options, one pipeline::localizeLog call, the files.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_common.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/io/floorplan.hpp"
#include "glassmap/io/log.hpp"
#include "glassmap/io/sensor_profile.hpp"
#include "glassmap/io/tum.hpp"
#include "glassmap/pipeline/localize_checks.hpp"
#include "glassmap/pipeline/localize_log.hpp"
#include "glassmap/pipeline/reports.hpp"

namespace glassmap {
namespace {

struct LocalizeArgs {
  LogReadOptions read;
  std::string map, log, out, json, spread;
  std::string model = "glass";
  std::string glass_as = "opaque";
  int particles = localize::FilterOptions{}.max_particles;
  int min_particles = localize::FilterOptions{}.min_particles;
  bool fixed = false;
  int beams = localize::LocalizeOptions{}.beams;
  std::string init;
  std::string units, layers;
  std::string laser_offset;
  std::uint64_t seed = 1;
  double sigma_hit = sensor::SensorParams{}.sigma_hit;
  bool sigma_hit_given = false;
  std::string sensor;
  double global_temperature = localize::FilterOptions{}.global_temperature;
  bool no_inject = false;
  bool no_self_calibrate = false;
  bool inject_always = false;
  double lost_share = localize::FilterOptions{}.contradiction_share;
  bool quiet = false;
  bool walls_only = false;
};

void run(const LocalizeArgs& a) {
  std::string scale_warning;
  const VectorMap map = cli::readPlan(a.map, a.units, a.layers, a.quiet, &scale_warning, !a.walls_only);
  // Localizing against a plan of the wrong scale gives a confident wrong answer: without an
  // explicit --units, refuse; with one, only warn.
  pipeline::checkLocalizationPlan(map, a.map, scale_warning, !a.units.empty());
  if (!scale_warning.empty() && !a.quiet) std::cerr << "glassmap: warning: " << scale_warning << "\n";
  LogReadOptions read = a.read;
  read.carmen.progress = cli::readProgress(!a.quiet && cli::stderrIsTerminal());
  read.ros2.pose_source = BagPoseSource::Odometry;  // the filter wants raw odometry, not SLAM poses
  const LaserLog log = cli::readLogReporting(a.log, read, a.quiet);
  if (log.scans.empty()) throw Error("the log holds no scan", a.log);

  pipeline::LocalizeOptions options;
  options.model = a.model;
  options.sensor.glass_as = sensor::parseGlassAs(a.glass_as);
  options.sensor.sigma_hit = a.sigma_hit;
  if (!a.sensor.empty()) {
    options.sensor = sensor::paramsFromProfile(readSensorProfile(a.sensor), options.sensor);
    if (a.sigma_hit_given) {  // an explicit option wins: one sigma for every beam
      options.sensor.sigma_hit = a.sigma_hit;
      options.sensor.sigma_hit_rel = 0.0;
    }
  }
  localize::LocalizeOptions& opt = options.filter;
  opt.beams = a.beams;
  opt.filter.max_particles = a.particles;
  opt.filter.min_particles = a.min_particles;
  opt.filter.adaptive = !a.fixed;
  if (a.no_inject && a.inject_always)
    throw Error("--no-inject and --inject-always exclude each other", {}, 0, "inject-always");
  opt.filter.recovery = a.no_inject       ? localize::Recovery::None
                        : a.inject_always ? localize::Recovery::Inject
                                          : localize::Recovery::Probe;
  opt.filter.contradiction_share = a.lost_share;
  opt.filter.seed = a.seed;
  opt.filter.global_temperature = a.global_temperature;
  // The model's parameters come from the data: a given profile, else refits on the way.
  opt.self_calibration.enabled = a.sensor.empty() && !a.no_self_calibrate;
  if (!a.init.empty()) {
    opt.init = cli::parsePose(a.init, "init");
    // A start outside the plan is a wrong frame or wrong units, never a run to trust.
    pipeline::checkInitialPose(map, *opt.init, a.map);
  }
  if (!a.laser_offset.empty()) opt.T_base_laser = cli::parsePose(a.laser_offset, "laser-offset");
  if (!a.quiet && cli::stderrIsTerminal())
    std::cerr << "localizing " << log.scans.size() << " scans with the " << a.model << " model...\n";
  const pipeline::LocalizeResult result = pipeline::localizeLog(log, map, options);
  const localize::LocalizeResult& r = result.run;
  const std::filesystem::path out_path(a.out);
  if (out_path.has_parent_path()) std::filesystem::create_directories(out_path.parent_path());
  writeTum(out_path, r.trajectory);
  if (!a.spread.empty()) {
    const std::filesystem::path spread_path(a.spread);
    if (spread_path.has_parent_path()) std::filesystem::create_directories(spread_path.parent_path());
    localize::writeSpreadCsv(spread_path, r);
  }

  const nlohmann::json summary = pipeline::localizeSummaryJson(result, options);
  if (!a.json.empty()) cli::writeJsonFile(a.json, summary);
  if (!a.quiet) {
    std::printf("%-18s %12s\n", "model", result.model.c_str());
    std::printf("%-18s %12zu\n", "scans", r.scans);
    std::printf("%-18s %12zu\n", "updates", r.updates);
    std::printf("%-18s %12.1f\n", "mean particles", r.mean_particles);
    std::printf("%-18s %12.3f\n", "ms per update", 1e3 * r.seconds_per_update);
    std::printf("%-18s %12.1f\n", "real-time factor", r.realTimeFactor());
    std::printf("%-18s %12zu  (random particles drawn: global start, probes)\n", "injected", r.injected);
    std::printf("%-18s %12zu  (looks for the robot elsewhere when the scans stopped fitting)\n", "probes", r.probes);
    std::printf("%-18s %12zu  (jumps of the estimate to another hypothesis)\n", "relocalizations", r.relocalizations);
    std::printf("%-18s %12zu  (scans that contradict the one before them: kidnapped, or the odometry jumped)\n",
                "breaks", r.breaks);
    const sensor::SensorParams& p = r.final_params;
    const double sum = p.z_hit + p.z_short + p.z_max + p.z_rand;
    std::printf(
        "%-18s %12.4f  (+ %.2f%% of the range; hit %.3f, short %.3f, max %.3f, random %.3f; glass lobe %.2f at %.1f "
        "deg, floor %.3f)\n",
        "sigma_hit m", p.sigma_hit, 100.0 * p.sigma_hit_rel, p.z_hit / sum, p.z_short / sum, p.z_max / sum,
        p.z_rand / sum, p.direct_peak, p.direct_sigma_deg, p.direct_floor);
    std::size_t applied = 0;
    for (const auto& f : r.calibrations) applied += f.applied;
    std::printf("%-18s %12zu  (%s)\n", "self-calibrations", applied,
                !opt.self_calibration.enabled ? (a.sensor.empty() ? "off" : "off: --sensor given")
                : applied                     ? "the model refitted to this log at trusted poses"
                                              : "no fit yet: too little trusted travel");
    if (r.converged)
      std::printf("%-18s %12s  (one tight mode from %.1f s on)\n", "converged", "yes", r.converged_at);
    else
      std::printf("%-18s %12s  (the cloud is still spread or split at the end: do not trust the pose)\n", "converged",
                  "NO");
    std::printf("wrote %s\n", a.out.c_str());
  }
}

const cli::Registrar reg(60, [](CLI::App& app) {
  auto a = std::make_shared<LocalizeArgs>();
  CLI::App* sub = app.add_subcommand(
      "localize",
      "Monte Carlo localization of a laser log against a floorplan (any format the io module reads,\n"
      "a DXF with a GLASS layer included). Uses the log's odometry and ranges only, never its laser\n"
      "poses; writes one T_map_laser estimate per scan as TUM.");
  sub->add_option("log", a->log, std::string(cli::kLogHelp) + "; bags: odometry poses (odom -> base -> laser)")
      ->required()
      ->check(CLI::ExistingPath);
  cli::addLogOptions(*sub, a->read);
  sub->add_option("--map", a->map, "floorplan: GeoJSON, GPKG, DXF, Shapefile, ...")
      ->required()
      ->check(CLI::ExistingFile);
  sub->add_option("-o,--output", a->out, "estimated trajectory (TUM)")->required();
  sub->add_flag("--walls-only", a->walls_only,
                "localize in the building alone: leave a glassmap plan's CLUTTER layer (furniture kept apart\n"
                "from the walls, read as walls by default) out, as a building drawing would");
  sub->add_option("--model", a->model, "sensor model")
      ->check(CLI::IsMember({"glass", "glass-paper", "beam", "field"}))
      ->capture_default_str();
  sub->add_option("--glass-as", a->glass_as, "what glass is to the beam and field models")
      ->check(CLI::IsMember({"opaque", "invisible"}))
      ->capture_default_str();
  sub->add_option("--particles", a->particles, "maximum (and initial) particle count")->capture_default_str();
  sub->add_option("--min-particles", a->min_particles, "minimum particle count of KLD sampling")->capture_default_str();
  sub->add_flag("--fixed-count", a->fixed, "keep --particles particles (no KLD sampling)");
  sub->add_option("--beams", a->beams, "beams per scan, spread evenly (0: all)")->capture_default_str();
  sub->add_option("--init", a->init, "initial laser pose x,y,theta [m,m,rad]; without it: global localization");
  sub->add_option("--laser-offset", a->laser_offset, "laser pose on the robot x,y,theta [m,m,rad] (default 0,0,0)");
  cli::addUnitsOption(*sub, a->units);
  cli::addLayersOption(*sub, a->layers);
  sub->add_option("--sigma-hit", a->sigma_hit,
                  "range std dev of the sensor models [m], the same for every beam (with --sensor: replaces the\n"
                  "profile's range noise)")
      ->capture_default_str()
      ->each([a](const std::string&) { a->sigma_hit_given = true; });
  sub->add_option("--sensor", a->sensor,
                  "sensor profile YAML (glassmap calibrate, or a map folder's sensor.yaml): the glass lobe\n"
                  "(peak, sigma, floor), the reflection rate, the mixture weights and the range noise beam by\n"
                  "beam, hypot(sigma_0, rel z) with the profile's sigma_0 (at least 2 cm: a floorplan is never\n"
                  "drawn to the millimetre) and growth rel")
      ->check(CLI::ExistingFile);
  sub->add_option("--global-temperature", a->global_temperature,
                  "global localization and probes: a broad hypothesis divides its particles' log-likelihoods by\n"
                  "this until it splits into modes")
      ->capture_default_str();
  sub->add_flag("--no-inject", a->no_inject, "never draw random particles while tracking (no recovery)");
  sub->add_flag("--no-self-calibrate", a->no_self_calibrate,
                "keep the sensor model's default parameters. By default (without --sensor) the range noise,\n"
                "mixture weights and glass response are refitted to the log at the poses the filter trusts\n"
                "(after 1 m of trusted travel, then each time it tripled)");
  sub->add_option("--lost-share", a->lost_share,
                  "a probe also starts when this share of the readings at the best particle (smoothed) runs\n"
                  "over 0.5 m through a wall and the sensor model cannot explain them")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  sub->add_flag("--inject-always", a->inject_always,
                "recover as plain augmented MCL does: random particles into the cloud whenever the likelihood\n"
                "drops, a global restart when it collapses. By default a drop (or readings through walls)\n"
                "starts a probe: random particles (kept where the last metres of scans fit, a quarter drawn\n"
                "near the estimate) as a rival hypothesis with a prior of 1e-4, which replaces the tracked\n"
                "cloud only when the scans that follow favour it by more than that prior");
  sub->add_option("--seed", a->seed, "random seed; the same seed gives the same estimate")->capture_default_str();
  sub->add_option("--json", a->json, "also write the summary as JSON");
  sub->add_option("--spread", a->spread,
                  "also write the particle spread per scan as CSV: t, spread_m (weighted RMS distance of\n"
                  "the particles from the estimate), particles, corrected (1 = measurement update),\n"
                  "relocalizations (jumps to another hypothesis so far), converged (1 = the cloud is one tight\n"
                  "mode from this scan to the end; poses with 0 came before convergence)");
  sub->add_flag("-q,--quiet", a->quiet, "print nothing on success");
  sub->callback([a] { run(*a); });
});

}  // namespace
}  // namespace glassmap
