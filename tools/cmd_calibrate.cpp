// glassmap calibrate LOG [--map FLOORPLAN] -o sensor.yaml: the sensor profile of the log's laser.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli_common.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/io/log.hpp"
#include "glassmap/io/sensor_profile.hpp"
#include "glassmap/pipeline/map_log.hpp"
#include "glassmap/pipeline/reports.hpp"

namespace glassmap {
namespace {

struct CalibrateArgs {
  LogReadOptions read;
  std::string log, map, units, layers, out, json, chart;
  int laser_id = 0;
  bool quiet = false;
  pipeline::MapOptions options;
};

void run(CalibrateArgs& a) {
  const auto t0 = std::chrono::steady_clock::now();
  const bool show_progress = !a.quiet && cli::stderrIsTerminal();
  LogReadOptions read = a.read;
  read.carmen.laser_id = a.laser_id;
  read.carmen.progress = cli::readProgress(show_progress);
  read.ros2.pose_source = BagPoseSource::Auto;
  const LaserLog log = cli::readLogReporting(a.log, read, a.quiet);
  VectorMap plan;
  if (!a.map.empty()) plan = cli::readPlan(a.map, a.units, a.layers, a.quiet);
  auto progress = [&](const char* stage, double f) {
    if (!show_progress) return;
    const std::string_view s(stage);
    if (s == "counts" || s == "angles") {
      std::fprintf(stderr, "\r%-8s %5.1f%%", stage, 100.0 * f);
      if (f >= 1.0) std::fputc('\n', stderr);
    } else if (f <= 0.0) {
      std::fprintf(stderr, "%s...\n", stage);
    }
  };
  if (show_progress)
    std::cerr << (a.map.empty() ? "mapping the log to calibrate against its own floorplan\n"
                                : "calibrating against " + a.map + "\n");
  const pipeline::CalibrateLogResult r =
      pipeline::calibrateLog(log, a.map.empty() ? nullptr : &plan, a.options, progress);
  SensorProfile profile = r.fit.profile;
  profile.source = pipeline::calibrationSource(a.log, a.map);
  writeSensorProfile(a.out, profile);
  if (!a.chart.empty()) renderCalibrationChart(a.chart, profile, r.fit.bins);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!a.json.empty()) {
    cli::writeJsonFile(a.json, pipeline::calibrationJson(profile, r, a.log, a.map, seconds));
  }
  for (const std::string& w : r.fit.warnings) std::cerr << "warning: " << w << "\n";
  if (!a.quiet) {
    const auto line = [](const char* name, const Estimate& e, const char* unit) {
      if (e.fitted)
        std::printf("%-24s %10.4g  +- %.2g %s\n", name, e.value, e.se, unit);
      else
        std::printf("%-24s %10.4g  (prior, not fitted) %s\n", name, e.value, unit);
    };
    std::printf("%-24s %zu (%zu aligned, median shift %.3f m / %.2f deg)\n", "scans used", r.fit.scans,
                r.fit.aligned_scans, r.fit.median_alignment_m, r.fit.median_alignment_deg);
    std::printf("%-24s %zu on walls, %zu on glass\n", "beams", profile.wall_beams, profile.glass_beams);
    if (r.fit.transient_panes > 0)
      std::printf("%-24s %zu glass segments, %.1f m, left out of the glass fit (people walking by)\n", "transients",
                  r.fit.transient_panes, r.fit.transient_length_m);
    line("range_sigma_m", profile.range_sigma_m, "m");
    line("range_sigma_rel", profile.range_sigma_rel, "");
    std::printf("%-24s %10.4g m against the walls, %.4g m within scans\n", "", r.fit.range_sigma_em_m,
                r.fit.range_sigma_local_m);
    line("w_hit", profile.w_hit, "");
    line("w_short", profile.w_short, "");
    line("w_max", profile.w_max, "");
    line("w_rand", profile.w_rand, "");
    line("lambda_short", profile.lambda_short, "1/m");
    line("direct_peak", profile.direct_peak, "");
    line("direct_sigma_deg", profile.direct_sigma_deg, "deg");
    line("direct_floor", profile.direct_floor, "");
    line("normal_lambda_per_deg", profile.normal_lambda_per_deg, "1/deg");
    line("normal_floor", profile.normal_floor, "");
    line("glass_offset_m", profile.glass_offset_m, "m");
    std::printf("%-24s %.2f\n", "seconds", seconds);
    std::printf("%-24s %s%s%s\n", "wrote", a.out.c_str(), a.json.empty() ? "" : (", " + a.json).c_str(),
                a.chart.empty() ? "" : (", " + a.chart).c_str());
  }
}

const cli::Registrar reg(38, [](CLI::App& app) {
  auto a = std::make_shared<CalibrateArgs>();
  CLI::App* cmd = app.add_subcommand(
      "calibrate",
      "Estimate the laser's sensor profile from a log: range noise and the hit/short/max/random weights\n"
      "(EM over wall beams, Probabilistic Robotics 6.3), the glass direct-return lobe (peak, sigma, floor),\n"
      "the reflected fraction and the range offset through panes (from beams that meet glass). Each scan's\n"
      "pose is first aligned to the walls. Without --map the log is mapped first and the profile fitted\n"
      "against its own floorplan, then refitted after a second mapping with the fitted thresholds.\n"
      "Use the profile with `glassmap map --sensor`.");
  cmd->add_option("log", a->log, std::string(cli::kLogHelp) + " with SLAM-corrected laser poses")
      ->required()
      ->check(CLI::ExistingPath);
  cli::addLogOptions(*cmd, a->read);
  cmd->add_option("--map", a->map,
                  "floorplan (GPKG, GeoJSON, DXF, Shapefile) in the frame of the log's laser poses, with\n"
                  "wall and glass segments; without it the log's own map is used")
      ->check(CLI::ExistingFile);
  cli::addUnitsOption(*cmd, a->units);
  cli::addLayersOption(*cmd, a->layers);
  cmd->add_option("-o,--output", a->out, "sensor profile to write (YAML)")->required();
  cmd->add_option("--json", a->json,
                  "also write the fit as JSON: every parameter with its standard error, the\n"
                  "per-angle table, the alignment figures and warnings");
  cmd->add_option("--chart", a->chart, "also draw the fitted lobes over the measured fractions (PNG)");
  cmd->add_option("--max-scans", a->options.calibration.max_scans, "scans used, spread evenly over the log")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option_function<std::string>(
         "--sigma-from",
         [a](const std::string& v) {
           a->options.calibration.sigma_source = v == "scan" ? sensor::SigmaSource::Local : sensor::SigmaSource::Walls;
         },
         "with --map: range noise from the residuals against the walls (walls, the default) or from\n"
         "neighbouring readings within each scan (scan: use it when the floorplan is only roughly drawn).\n"
         "Without --map it always comes from the scans")
      ->check(CLI::IsMember({"walls", "scan"}));
  cmd->add_flag("!--no-align", a->options.calibration.align_scans,
                "use the logged poses as they are (pose error then counts as range noise)");
  cmd->add_option("--min-glass-beams", a->options.calibration.min_glass_beams,
                  "fewer beams on glass: the glass parameters keep their defaults")
      ->capture_default_str();
  cmd->add_option("--rounds", a->options.calibration_rounds,
                  "without --map: fit and re-map at most this many times (as map --calibration-rounds)")
      ->capture_default_str()
      ->check(CLI::Range(1, 5));
  cmd->add_option("--resolution", a->options.mapping.resolution, "without --map: cell size of the mapping [m]")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--no-return-range", a->options.mapping.beams.no_return_range,
                  "without --map: max-range readings clear free space up to this range [m]; 0: the range cap")
      ->capture_default_str();
  cmd->add_option("--laser-id", a->laser_id, "keep only scans of this CARMEN laser (0: all)")->capture_default_str();
  cmd->add_flag("-q,--quiet", a->quiet, "no progress, no summary");
  cmd->callback([a] { run(*a); });
});

}  // namespace
}  // namespace glassmap
