// glassmap simulate SCENE -o DIR: a laser log with ground truth from a scene.
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli_common.hpp"
#include "glassmap/core/atomic_file.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/io/carmen.hpp"
#include "glassmap/io/floorplan.hpp"
#include "glassmap/io/tum.hpp"
#include "glassmap/sim/sensor_profile.hpp"
#include "glassmap/sim/simulator.hpp"

namespace glassmap {
namespace {

namespace fs = std::filesystem;

struct SimulateArgs {
  std::string scene;
  std::string out;
  std::string sensor;
  std::uint64_t seed = 1;
  double duration = 0.0;
  double people = -1.0;
  double range_sigma = -1.0;
  double rate = -1.0;
  double kidnap_at = -1.0;
  double kidnap_along = 0.0;
  std::string kidnap_to;
  bool quiet = false;
};

nlohmann::json poseJson(const Pose2& p) { return {p.x(), p.y(), p.theta}; }

nlohmann::json laserJson(const sim::LaserSpec& l) {
  return {{"model", l.model},
          {"fov_deg", rad2deg(l.fov)},
          {"resolution_deg", rad2deg(l.resolution)},
          {"max_range", l.max_range},
          {"rate", l.rate},
          {"range_sigma", l.range_sigma},
          {"range_sigma_rel", l.range_sigma_rel},
          {"dropout_rate", l.dropout_rate},
          {"random_rate", l.random_rate},
          {"short_rate", l.short_rate},
          {"short_lambda", l.short_lambda}};
}

nlohmann::json glassJson(const sim::GlassPhysics& g) {
  return {{"n_glass", g.n_glass},
          {"direct_sigma_deg", g.direct_sigma_deg},
          {"direct_peak", g.direct_peak},
          {"direct_floor", g.direct_floor},
          {"reflection_gain", g.reflection_gain},
          {"reflection_floor", g.reflection_floor},
          {"pane_thickness", g.pane_thickness},
          {"max_bounces", g.max_bounces}};
}

nlohmann::json sceneJson(const sim::Scene& s) {
  const auto& m = s.motion;
  return {{"name", s.name},
          {"segments", s.map.segments.size()},
          {"glass_segments", s.map.count(Material::Glass)},
          {"laser", laserJson(s.laser)},
          {"glass", glassJson(s.glass)},
          {"motion",
           {{"odom_trans_sigma", m.odom_trans_sigma},
            {"odom_rot_sigma", m.odom_rot_sigma},
            {"odom_rot_per_m", m.odom_rot_per_m},
            {"odom_scale_bias", m.odom_scale_bias},
            {"odom_drift_deg_per_m", rad2deg(m.odom_drift_per_m)},
            {"slam_sigma_xy", m.slam_sigma_xy},
            {"slam_sigma_theta_deg", rad2deg(m.slam_sigma_theta)}}},
          {"people",
           {{"density", s.people.density},
            {"radius", s.people.radius},
            {"speed", s.people.speed},
            {"group_size", s.people.group_size}}},
          {"trajectory",
           {{"waypoints", s.trajectory.waypoints.size()},
            {"round_trip", s.trajectory.round_trip},
            {"speed", s.trajectory.speed},
            {"turn_rate_deg", rad2deg(s.trajectory.turn_rate)}}}};
}

void run(const SimulateArgs& args) {
  const auto t0 = std::chrono::steady_clock::now();
  sim::Scene scene = sim::loadScene(args.scene);
  if (!args.sensor.empty()) sim::applySensorProfile(scene, sim::sensorProfile(args.sensor, "--sensor"));
  if (args.people >= 0) scene.people.density = args.people;
  if (args.range_sigma >= 0) scene.laser.range_sigma = args.range_sigma;
  if (args.rate > 0) scene.laser.rate = args.rate;
  sim::SimOptions options;
  options.seed = args.seed;
  options.duration_limit = args.duration;
  options.repeat_until_limit = args.duration > 0;
  options.kidnap.time = args.kidnap_at;
  options.kidnap.along = args.kidnap_along;
  if (!args.kidnap_to.empty()) options.kidnap.to = cli::parsePose(args.kidnap_to, "kidnap-to");
  if (!args.quiet)
    std::cerr << "simulating " << scene.name << " with " << (scene.sensor.empty() ? scene.laser.model : scene.sensor)
              << " (seed " << args.seed << ")...\n";
  const sim::SimResult result = sim::simulate(scene, options);

  const fs::path dir(args.out);
  fs::create_directories(dir);
  writeCarmenLog(dir / "log.clf", result.log);
  writeTum(dir / "groundtruth.tum", result.ground_truth);
  writeFloorplan(dir / "floorplan.gpkg", scene.map);
  writeFloorplan(dir / "floorplan.geojson", scene.map);
  // Per-beam outcomes, scan-major, one byte each (codes as in BeamOutcome): for render --outcomes.
  writeAtomically(dir / "outcomes.bin", [&](const fs::path& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    for (const auto& scan : result.outcomes)
      out.write(reinterpret_cast<const char*>(scan.data()), static_cast<std::streamsize>(scan.size()));
    if (!out) throw Error("cannot write", (dir / "outcomes.bin").string());
  });

  std::size_t beams = 0;
  nlohmann::json counts, codes = nlohmann::json::array();
  for (std::size_t i = 0; i < result.counts.size(); ++i) {
    counts[sim::toString(static_cast<sim::BeamOutcome>(i))] = result.counts[i];
    codes.push_back(sim::toString(static_cast<sim::BeamOutcome>(i)));
    beams += result.counts[i];
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  nlohmann::json meta = {{"scene", sceneJson(scene)},
                         {"seed", args.seed},
                         {"scans", result.log.scans.size()},
                         {"beams", beams},
                         {"duration_s", result.ground_truth.empty() ? 0.0 : result.ground_truth.back().timestamp},
                         {"outcome_counts", counts},
                         {"outcome_codes", codes},
                         // The sensor truth a calibration is scored against: the profile (null: the laser preset)
                         // and the numbers the run used, after the scene's and the command line's overrides.
                         {"sensor",
                          {{"profile", scene.sensor.empty() ? nlohmann::json(nullptr) : nlohmann::json(scene.sensor)},
                           {"laser", laserJson(scene.laser)},
                           {"glass", glassJson(scene.glass)}}},
                         {"kidnap", nullptr},
                         {"seconds", seconds}};
  if (!result.ground_truth.empty()) {
    // The true first laser pose, and the same as `glassmap localize --init` takes it.
    const Pose2& p0 = result.ground_truth.front().pose;
    char init[128];
    std::snprintf(init, sizeof init, "%.17g,%.17g,%.17g", p0.x(), p0.y(), p0.theta);
    meta["start_pose"] = poseJson(p0);
    meta["start_init"] = init;
  }
  if (result.kidnap) {
    const sim::KidnapEvent& k = *result.kidnap;
    meta["kidnap"] = {{"time", k.time},
                      {"scan", k.scan},
                      {"from", poseJson(k.from)},
                      {"to", poseJson(k.to)},
                      {"distance_m", k.distance()},
                      {"heading_change_deg", rad2deg(std::abs(angleDiff(k.to.theta, k.from.theta)))},
                      {"along_m", options.kidnap.to ? nlohmann::json(nullptr) : nlohmann::json(options.kidnap.along)}};
  }
  cli::writeJsonFile(dir / "meta.json", meta);
  if (!args.quiet) {
    std::printf("%-18s %12s\n", "scans", std::to_string(result.log.scans.size()).c_str());
    std::printf("%-18s %12zu\n", "beams", beams);
    for (auto& [name, n] : counts.items())
      std::printf("  %-16s %12zu  (%.2f%%)\n", name.c_str(), n.get<std::size_t>(),
                  beams ? 100.0 * n.get<double>() / static_cast<double>(beams) : 0.0);
    if (result.kidnap)
      std::printf("%-18s %10.2f m  (at %.2f s)\n", "kidnapped", result.kidnap->distance(), result.kidnap->time);
    std::printf("%-18s %12.2f\n", "seconds", seconds);
    std::printf("wrote %s/{log.clf,groundtruth.tum,floorplan.gpkg,floorplan.geojson,outcomes.bin,meta.json}\n",
                dir.string().c_str());
  }
}

const cli::Registrar reg(30, [](CLI::App& app) {
  auto args = std::make_shared<SimulateArgs>();
  CLI::App* sub =
      app.add_subcommand("simulate",
                         "Simulate a laser log with ground truth from a scene (maps/<scene>/scene.yaml):\n"
                         "writes DIR/log.clf (CARMEN), DIR/groundtruth.tum, DIR/floorplan.gpkg + .geojson (the true\n"
                         "segments), DIR/outcomes.bin (one byte per beam: its physical outcome) and DIR/meta.json.");
  sub->add_option("scene", args->scene, "scene YAML file")->required()->check(CLI::ExistingFile);
  sub->add_option("-o,--output", args->out, "output directory (created if missing)")->required();
  sub->add_option("--seed", args->seed, "random seed; the same seed gives the same log")->capture_default_str();
  sub->add_option("--duration", args->duration,
                  "simulate this many seconds, driving the trajectory back and forth (0: once)")
      ->capture_default_str();
  sub->add_option("--people", args->people, "override the scene's people density [per 100 m^2]");
  std::string names;
  for (const std::string& n : sim::sensorProfileNames()) names += "  " + n + "\n";
  sub->add_option("--sensor", args->sensor,
                  "simulate this sensor profile instead of the scene's laser: its geometry, range noise,\n"
                  "spurious readings (dropouts, random, short) and glass response replace the scene's laser\n"
                  "and glass keys (the mounting and max_bounces stay); meta.json records every number\n"
                  "(maps/README.md, \"Sensor profiles\"). Names:\n" +
                      names + "  random:SEED  (drawn reproducibly from the ranges the named ones span)");
  sub->add_option("--range-sigma", args->range_sigma, "override the laser's range noise [m] (after --sensor)");
  sub->add_option("--rate", args->rate, "override the laser's scan rate [Hz] (after --sensor)")
      ->check(CLI::PositiveNumber);
  CLI::Option* at = sub->add_option(
      "--kidnap-at", args->kidnap_at,
      "kidnap the robot at this time [s]: the first scan at or after it sees the robot elsewhere,\n"
      "the odometry records no motion for the jump and then integrates the real motion again;\n"
      "meta.json gets the kidnap time, scan and true poses before/after (truth jumps in groundtruth.tum)");
  sub->add_option("--kidnap-along", args->kidnap_along,
                  "with --kidnap-at: jump this far ahead along the trajectory, which goes on from there [m]")
      ->needs(at)
      ->capture_default_str();
  sub->add_option("--kidnap-to", args->kidnap_to,
                  "with --kidnap-at: jump to this base pose x,y,theta [m,m,rad] instead; the rest of the\n"
                  "trajectory moves rigidly with it (keep it in free space)")
      ->needs(at)
      ->excludes("--kidnap-along");
  sub->add_flag("-q,--quiet", args->quiet, "print nothing on success");
  sub->callback([args] { run(*args); });
});

}  // namespace
}  // namespace glassmap
