// End-to-end localization on the simulated scenes with the true floorplan as the map, 15 beams,
// fixed seeds. Assertions are on success rates over several seeds, not on one lucky run.
#include <gtest/gtest.h>

#include <cstdio>
#include <functional>

#include "glassmap/eval/trajectory.hpp"
#include "glassmap/pipeline/localize_log.hpp"
#include "glassmap/sim/simulator.hpp"

namespace glassmap::localize {
namespace {

struct RunSpec {
  std::string scene;
  std::string model = "glass";
  sensor::GlassAs glass_as = sensor::GlassAs::Opaque;
  std::uint64_t seed = 1;
  double duration = 0.0;  // seconds simulated, 0 = the whole trajectory
  bool global = false;    // no initial pose
  int particles = 500;
  int beams = 15;
  sim::Kidnap kidnap{};        // none by default
  bool self_calibrate = true;  // the model refitted to the log on the way (the default)
  Recovery recovery = Recovery::Probe;
  std::function<void(sim::Scene&)> tweak;
  bool declare_mount = true;  // localize with the scene's laser mounting (false: odometry read as the laser's)
};

RunSpec spec(std::string scene, std::uint64_t seed, std::string model = "glass") {
  RunSpec s;
  s.scene = std::move(scene);
  s.seed = seed;
  s.model = std::move(model);
  return s;
}

struct RunResult {
  eval::TrajectoryErrors errors;
  LocalizeResult run;
};

RunResult runScene(const RunSpec& spec) {
  sim::Scene scene = sim::loadScene(std::string(GLASSMAP_SOURCE_DIR) + "/maps/" + spec.scene + "/scene.yaml");
  if (spec.tweak) spec.tweak(scene);
  sim::SimOptions so;
  so.seed = spec.seed;
  so.duration_limit = spec.duration;
  so.repeat_until_limit = spec.duration > 0 && spec.kidnap.time >= 0;
  so.kidnap = spec.kidnap;
  const sim::SimResult sim = sim::simulate(scene, so);

  pipeline::LocalizeOptions options;
  options.model = spec.model;
  options.sensor.glass_as = spec.glass_as;
  LocalizeOptions& lo = options.filter;
  lo.beams = spec.beams;
  lo.filter.max_particles = spec.particles;
  lo.filter.seed = spec.seed;
  lo.self_calibration.enabled = spec.self_calibrate;
  lo.filter.recovery = spec.recovery;
  if (!spec.global) lo.init = sim.ground_truth.front().pose;
  if (spec.declare_mount) lo.T_base_laser = scene.laser.T_base_laser;
  RunResult r;
  r.run = pipeline::localizeLog(sim.log, scene.map, options).run;
  r.errors = eval::evaluateTrajectory(sim.ground_truth, r.run.trajectory);
  std::printf("  %-15s %-12s %-9s seed %llu: ATE rmse %.4f max %.3f m, %.1f particles, %.3f ms/update\n",
              spec.scene.c_str(), spec.model.c_str(), std::string(toString(spec.glass_as)).c_str(),
              static_cast<unsigned long long>(spec.seed), r.errors.rmse, r.errors.max, r.run.mean_particles,
              1e3 * r.run.seconds_per_update);
  return r;
}

bool tracks(const eval::TrajectoryErrors& e) { return e.rmse < 0.10 && e.max < 0.5; }

const std::vector<std::uint64_t> kSeeds{1, 2, 3};

TEST(LocalizeE2E, GlassModelTracksThePaperCorridor) {
  int ok = 0;
  for (auto seed : kSeeds) ok += tracks(runScene(spec("paper-corridor", seed)).errors);
  EXPECT_EQ(ok, static_cast<int>(kSeeds.size()));
}

TEST(LocalizeE2E, GlassModelTracksTheGlassCorridor) {
  int ok = 0;
  for (auto seed : kSeeds) ok += tracks(runScene(spec("glass-corridor", seed)).errors);
  EXPECT_EQ(ok, static_cast<int>(kSeeds.size()));
}

TEST(LocalizeE2E, BeamModelWithOpaqueGlassFailsInTheGlassCorridor) {
  // The paper's "Two G" failure: glass on both sides, most beams pass through the panes that the
  // beam model with its fixed parameters expects to echo, the likelihood drops, and plain augmented
  // MCL (the paper's filter) scatters the cloud. With the defaults (the model refitted to the log
  // learns that a third of its readings are "random"; a drop starts a probe that must win a
  // likelihood-ratio test) the beam model tracks, if several times less precisely than the glass
  // model.
  int failed = 0;
  for (auto seed : kSeeds) {
    RunSpec fixed_glass = spec("glass-corridor", seed), fixed_beam = spec("glass-corridor", seed, "beam");
    fixed_glass.self_calibrate = fixed_beam.self_calibrate = false;
    fixed_glass.recovery = fixed_beam.recovery = Recovery::Inject;
    const double glass = runScene(fixed_glass).errors.rmse;
    const auto beam = runScene(fixed_beam).errors;
    failed += !tracks(beam) && beam.rmse > 3.0 * glass;
    const double glass_fitted = runScene(spec("glass-corridor", seed)).errors.rmse;
    const auto beam_fitted = runScene(spec("glass-corridor", seed, "beam")).errors;
    EXPECT_TRUE(tracks(beam_fitted)) << seed;
    EXPECT_GT(beam_fitted.rmse, 3.0 * glass_fitted) << seed;
  }
  EXPECT_GE(failed, 2);
}

TEST(LocalizeE2E, GlassModelIsAsAccurateAsTheBeamModelWithoutGlass) {
  for (auto seed : kSeeds) {
    const auto glass = runScene(spec("no-glass", seed)).errors;
    const auto beam = runScene(spec("no-glass", seed, "beam")).errors;
    EXPECT_TRUE(tracks(glass) && tracks(beam)) << seed;
    EXPECT_LT(glass.rmse, 1.25 * beam.rmse + 0.005) << seed;
  }
}

TEST(LocalizeE2E, ALaserOffTheTurningAxisTracks) {
  // The laser 0.3 m ahead of the robot's turning axis, the office floor's tour: turning in place,
  // the laser swings on an arc, so each 1 deg update reads "turn 90 deg, move 5 mm, turn back" to
  // the motion model, whose heading takes the noise of the turn alone (motion_model.hpp). Declared
  // (--laser-offset), it tracks as a laser on the axis does: 4.6 mm, max 0.020 m (the book's noise
  // on both rotations: 6.8 mm, max 0.057). Undeclared, the robot's odometry read as the laser's is
  // wrong by the arc at every turn, and the filter follows it loosely: over scene seeds 1-3 RMSE
  // 0.92 / 0.21 / 0.16 m, max 4.7 / 1.2 / 0.8 m (seed 1 loses the robot for a while and finds it
  // again; the book's noise: 1.93 m off on seed 1). One seed alone says little either way: with the
  // motion step's earlier random stream the same seeds gave 0.19 / 0.22 / 0.28 m, max 0.7 / 1.3 /
  // 1.7 m.
  const auto run = [](std::uint64_t seed, bool declared) {
    RunSpec m = spec("office-floor", seed);
    m.particles = 2000;
    m.tweak = [](sim::Scene& s) { s.laser.T_base_laser = Pose2(0.3, 0.0, 0.0); };
    m.declare_mount = declared;
    return runScene(m).errors;
  };
  const auto declared = run(1, true);
  EXPECT_LT(declared.rmse, 0.006);
  EXPECT_LT(declared.max, 0.04);
  std::vector<double> rmse, max;
  for (const std::uint64_t seed : {1, 2, 3}) {
    const auto e = run(seed, false);
    rmse.push_back(e.rmse);
    max.push_back(e.max);
  }
  std::sort(rmse.begin(), rmse.end());
  std::sort(max.begin(), max.end());
  EXPECT_LT(rmse[1], 0.25);
  EXPECT_LT(max[1], 1.5);
}

TEST(LocalizeE2E, GlassModelCopesWithBiasedOdometryAndPeople) {
  int ok = 0;
  for (auto seed : kSeeds) {
    RunSpec r = spec("glass-corridor", seed);
    r.tweak = [](sim::Scene& s) {
      s.motion.odom_scale_bias = 0.03;           // odometry reads 3 % long
      s.motion.odom_drift_per_m = deg2rad(2.0);  // and drifts 2 deg per metre
      s.people.density = 2.0;                    // people walking past in groups of three
      s.people.group_size = 3;
    };
    ok += tracks(runScene(r).errors);
  }
  EXPECT_EQ(ok, static_cast<int>(kSeeds.size()));
}

TEST(LocalizeE2E, GlassModelRecoversFromAKidnappingInThePaperCorridor) {
  // Carried 1 m ahead along the corridor at 15 s, without odometry: the filter must notice and
  // find the robot again from the scans alone (random particle injection / global restart).
  int recovered = 0;
  for (auto seed : kSeeds) {
    RunSpec k = spec("paper-corridor", seed);
    k.duration = 60.0;
    k.kidnap.time = 15.0;
    k.kidnap.along = 1.0;
    const RunResult r = runScene(k);
    const auto& e = r.errors;
    bool before = true, lost = false, after = true;
    for (std::size_t i = 0; i < e.times.size(); ++i) {
      if (e.times[i] < 15.0) before = before && e.position_errors[i] < 0.1;
      if (e.times[i] >= 15.0 && e.times[i] < 15.5) lost = lost || e.position_errors[i] > 0.5;
      if (e.times[i] > 45.0) after = after && e.position_errors[i] < 0.2;
    }
    EXPECT_TRUE(before) << seed;
    EXPECT_TRUE(lost) << seed;  // the kidnapping did throw the estimate off
    recovered += before && lost && after;
  }
  EXPECT_GE(recovered, 2);
}

TEST(LocalizeE2E, KidnapsFarAlongThePaperCorridorRecover) {
  // Carried 8 or 12 m ahead along the corridor at 15 s without odometry: the view barely changes
  // (the side walls look the same from anywhere along it; only its ends, doors and panes differ),
  // so neither the scans against each other (no break at 30%) nor one scan against the plan says
  // where the robot went. Its probes are drawn where the scans of the last 2 m fit, their best
  // poses climbed, and may not take over while still spread over the floor
  // (FilterOptions::probe_from_scan). Recovered: within 0.2 m from some time on to the end, with
  // at least 10 s left (tools/loc_kidnap.py).
  int recovered = 0, runs = 0;
  for (double along : {8.0, 12.0})
    for (std::uint64_t seed : {1, 2, 3, 4}) {
      RunSpec k = spec("paper-corridor", seed);
      k.duration = 75.0;
      k.kidnap.time = 15.0;
      k.kidnap.along = along;
      const auto& e = runScene(k).errors;
      double t_rec = -1.0;
      for (std::size_t i = e.times.size(); i-- > 0 && e.times[i] >= 15.0 && e.position_errors[i] < 0.2;)
        t_rec = e.times[i];
      const bool ok = t_rec >= 0 && e.times.back() - t_rec >= 10.0;
      std::printf("  kidnap %.0f m seed %llu: %s\n", along, static_cast<unsigned long long>(seed),
                  ok ? "recovered" : "not recovered");
      recovered += ok;
      ++runs;
    }
  EXPECT_GE(recovered, 6) << "of " << runs;  // 7 of 8; e982322 (uniform probes): 3
}

TEST(LocalizeE2E, APlaceTheEstimateJumpedToIsNoAnswerUntilTheRobotMovedOn) {
  // Kidnapped 2 m along the corridor at 15 s: the estimate jumps to the robot's new place a few
  // seconds later. A run that ends soon after says converged: false (the new place has only the
  // scans since its probe for it, LocalizeOptions::converged_after_jump); one that goes on says
  // converged, and right.
  for (const double duration : {24.0, 60.0}) {
    RunSpec k = spec("paper-corridor", 1);
    k.duration = duration;
    k.kidnap.time = 15.0;
    k.kidnap.along = 2.0;
    const RunResult r = runScene(k);
    ASSERT_GE(r.run.relocalizations, 1u) << duration;
    const auto& e = r.errors;
    std::printf("  %.0f s: converged %d at %.1f s, final error %.3f m\n", duration, r.run.converged, r.run.converged_at,
                e.position_errors.back());
    if (duration < 30.0) {
      EXPECT_FALSE(r.run.converged);
    } else {
      EXPECT_TRUE(r.run.converged);
      EXPECT_LT(e.position_errors.back(), 0.2);
    }
  }
}

TEST(LocalizeE2E, AGlobalStartNeverEndsConfidentOnTheMirrorImage) {
  // no-glass is symmetric under a half turn but for doors 1 m apart. Seed 3 (the command's
  // defaults: 2,000 particles): the global start won the mirror image as the robot entered the
  // room, and every recheck drawn over the floor sank under it by the floor's size before it could
  // show the robot's place, so the run ended converged 28 m off. The rechecks of an estimate not
  // yet trusted are weighed by the best place they find: the run ends converged and right.
  RunSpec g = spec("no-glass", 3);
  g.global = true;
  g.particles = 2000;
  const RunResult r = runScene(g);
  const double final_error = r.errors.position_errors.back();
  std::printf("  converged %d at %.1f s, final error %.3f m\n", r.run.converged, r.run.converged_at, final_error);
  EXPECT_TRUE(r.run.converged);
  EXPECT_LT(final_error, 0.5);
}

TEST(LocalizeE2E, GlobalLocalizationConvergesOnTheOfficeFloor) {
  int converged = 0;
  for (auto seed : kSeeds) {
    if (converged >= 2) break;  // the assertion holds already: the third tour costs a minute of CI
    // No initial pose: 50,000 particles over the 62 x 40 m floor, the whole 5-minute tour. The
    // long main corridor is ambiguous (its far end looks like its near end, doors repeat every
    // 6 m), so convergence may take until the robot turns into a side corridor.
    RunSpec g = spec("office-floor", seed);
    g.global = true;
    g.particles = 50000;
    const RunResult r = runScene(g);
    // Converged: the last 100 s of the run stay within 0.2 m of the truth.
    const auto& e = r.errors;
    const double t_end = e.times.back();
    bool ok = t_end > 200.0;
    for (std::size_t i = 0; i < e.times.size(); ++i)
      if (e.times[i] > t_end - 100.0 && e.position_errors[i] > 0.2) ok = false;
    std::printf("  seed %llu: %s\n", static_cast<unsigned long long>(seed), ok ? "converged" : "not converged");
    converged += ok;
  }
  EXPECT_GE(converged, 2);
}

}  // namespace
}  // namespace glassmap::localize
