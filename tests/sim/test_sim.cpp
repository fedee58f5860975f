#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "glassmap/core/error.hpp"

#include "glassmap/geometry/optics.hpp"
#include "glassmap/geometry/ray_caster.hpp"
#include "glassmap/io/carmen.hpp"
#include "glassmap/sim/simulator.hpp"

using namespace glassmap;
using sim::BeamOutcome;
namespace fs = std::filesystem;

namespace {

const fs::path kMaps = fs::path(GLASSMAP_SOURCE_DIR) / "maps";

std::size_t count(const sim::SimResult& r, BeamOutcome o) { return r.counts[static_cast<std::size_t>(o)]; }

// A pane at x = 2 (thickness t) in front of a wall at x = 5; a one-beam laser driven from the
// origin at heading `heading_deg` so that the beam meets the pane at that incidence.
sim::Scene paneScene(double heading_deg, double thickness = 0.01) {
  sim::Scene s;
  s.name = "pane";
  s.map.segments.push_back({Vec2(2, -50), Vec2(2, 50), Material::Glass, thickness});
  s.map.segments.push_back({Vec2(5, -50), Vec2(5, 50), Material::Wall, 0.1});
  s.map.segments.push_back({Vec2(-20, -50), Vec2(-20, 50), Material::Wall, 0.1});
  s.laser.fov = deg2rad(0.1);
  s.laser.resolution = deg2rad(1.0);  // a single beam straight ahead
  s.laser.max_range = 80;
  s.laser.rate = 2000;
  s.laser.range_sigma = 0.0;
  s.motion = {};
  s.motion.slam_sigma_xy = 0;
  s.motion.slam_sigma_theta = 0;
  const double h = deg2rad(heading_deg);
  s.trajectory.waypoints = {Vec2(0, 0), Vec2(0.5 * std::cos(h), 0.5 * std::sin(h))};
  s.trajectory.speed = 0.5;  // 1 s at 2 kHz: 2001 scans of one beam
  s.trajectory.start_heading = std::nan("");
  return s;
}

}  // namespace

TEST(Simulator, DirectReturnsAreLikelierAtNormalIncidence) {
  const sim::SimResult straight = sim::simulate(paneScene(0.0), {7});
  const sim::SimResult oblique = sim::simulate(paneScene(45.0), {7});
  ASSERT_EQ(straight.log.scans.size(), 2001u);
  ASSERT_EQ(straight.log.scans.front().ranges.size(), 1u);
  const double n = static_cast<double>(straight.log.scans.size());
  // At 0 deg the direct lobe peaks (0.9); at 45 deg it is exp(-45^2 / (2 * 2^2)), nothing.
  EXPECT_GT(count(straight, BeamOutcome::GlassDirect) / n, 0.8);
  EXPECT_EQ(count(oblique, BeamOutcome::GlassDirect), 0u);
  // Direct returns read the range to the glass.
  for (std::size_t k = 0; k < straight.log.scans.size(); ++k)
    if (straight.outcomes[k][0] == BeamOutcome::GlassDirect) {
      const double x = straight.ground_truth[k].pose.x();
      EXPECT_NEAR(straight.log.scans[k].ranges[0], 2.0 - x, 1e-4);
    }
}

TEST(Simulator, TransmissionIsLongerByTheElongation) {
  sim::Scene s = paneScene(0.0, 0.08);
  s.glass.direct_peak = 0.0;
  s.glass.reflection_gain = 0.0;
  const sim::SimResult r = sim::simulate(s, {3});
  const double elongation = paneRangeElongation(0.08, 0.0, s.glass.n_glass);
  EXPECT_NEAR(elongation, 0.08 * 0.5, 1e-12);
  for (std::size_t k = 0; k < r.log.scans.size(); ++k) {
    ASSERT_EQ(r.outcomes[k][0], BeamOutcome::GlassTransmitted);
    EXPECT_NEAR(r.log.scans[k].ranges[0], 5.0 - r.ground_truth[k].pose.x() + elongation, 1e-4);
  }
}

TEST(Simulator, SpecularReflectionReadsTheWholeMirroredPath) {
  sim::Scene s = paneScene(45.0);
  s.glass.direct_peak = 0.0;
  s.glass.reflection_gain = 1e9;  // always reflect
  const sim::SimResult r = sim::simulate(s, {3});
  for (std::size_t k = 0; k < r.log.scans.size(); ++k) {
    ASSERT_EQ(r.outcomes[k][0], BeamOutcome::GlassReflected);
    // Mirrored at 45 deg the beam travels back to the wall at x = -20: the path length is the
    // distance from the robot's mirror image (4 - x, y) to that wall along the same 45 deg line.
    const Vec2 p = r.ground_truth[k].pose.t;
    const double expected = (2.0 - p.x()) * std::sqrt(2.0) + (2.0 + 20.0) * std::sqrt(2.0);
    EXPECT_NEAR(r.log.scans[k].ranges[0], expected, 1e-4);
  }
}

TEST(Simulator, SameSeedSameLogOtherSeedOtherLog) {
  const sim::Scene scene = sim::loadScene(kMaps / "glass-corridor" / "scene.yaml");
  sim::SimOptions o;
  o.seed = 11;
  o.duration_limit = 3.0;
  const sim::SimResult a = sim::simulate(scene, o);
  const sim::SimResult b = sim::simulate(scene, o);
  o.seed = 12;
  const sim::SimResult c = sim::simulate(scene, o);
  ASSERT_EQ(a.log.scans.size(), b.log.scans.size());
  bool all_equal = true, any_diff = false;
  for (std::size_t k = 0; k < a.log.scans.size(); ++k) {
    all_equal = all_equal && a.log.scans[k].ranges == b.log.scans[k].ranges;
    any_diff = any_diff || a.log.scans[k].ranges != c.log.scans[k].ranges;
  }
  EXPECT_TRUE(all_equal);
  EXPECT_TRUE(any_diff);
}

// The per-outcome counts of a fixed-seed run agree with what the physics predicts beam by beam:
// for each beam whose first surface is glass, P(direct) = peak exp(-theta^2 / 2 sigma^2) and
// P(reflect) = (1 - P(direct)) R(theta). Computed here independently of the simulator's tracing.
TEST(Simulator, PaperCorridorOutcomeCountsMatchThePhysics) {
  const sim::Scene scene = sim::loadScene(kMaps / "paper-corridor" / "scene.yaml");
  ASSERT_EQ(scene.map.count(Material::Glass), 6u);
  const sim::SimResult r = sim::simulate(scene, {42});
  const RayCaster caster(scene.map);
  double e_direct = 0, v_direct = 0, e_reflect = 0, v_reflect = 0;
  std::size_t first_glass = 0;
  for (std::size_t k = 0; k < r.log.scans.size(); ++k) {
    const LaserScan& scan = r.log.scans[k];
    const Pose2& pose = r.ground_truth[k].pose;
    for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
      const RayHit hit = caster.cast(pose.t, pose.theta + scan.beamAngle(i), scan.max_range);
      if (!hit.hit() || hit.material != Material::Glass) continue;
      ++first_glass;
      const double th = hit.incidence;
      const double sigma = deg2rad(scene.glass.direct_sigma_deg);
      const double pd = scene.glass.direct_peak * std::exp(-th * th / (2 * sigma * sigma));
      const double pr = (1 - pd) * std::min(1.0, scene.glass.reflection_gain * reflectance(th));
      e_direct += pd;
      v_direct += pd * (1 - pd);
      e_reflect += pr;
      v_reflect += pr * (1 - pr);
    }
  }
  const double direct = static_cast<double>(count(r, BeamOutcome::GlassDirect));
  const double reflected = static_cast<double>(count(r, BeamOutcome::GlassReflected));
  EXPECT_GT(first_glass, 10000u);
  EXPECT_GT(e_direct, 100.0);
  EXPECT_NEAR(direct, e_direct, 5 * std::sqrt(v_direct) + 0.02 * e_direct);
  EXPECT_NEAR(reflected, e_reflect, 5 * std::sqrt(v_reflect) + 0.02 * e_reflect);
  // Most glass beams go through: transmitted is the largest glass outcome.
  EXPECT_GT(count(r, BeamOutcome::GlassTransmitted), count(r, BeamOutcome::GlassReflected));
  EXPECT_GT(count(r, BeamOutcome::GlassTransmitted), count(r, BeamOutcome::GlassDirect));
  EXPECT_EQ(count(r, BeamOutcome::Person), 0u);
}

TEST(Simulator, PeopleCutBeamsShort) {
  sim::Scene scene = sim::loadScene(kMaps / "no-glass" / "scene.yaml");
  scene.people.density = 3.0;
  scene.people.group_size = 3;
  sim::SimOptions o;
  o.seed = 5;
  o.duration_limit = 20.0;
  const sim::SimResult r = sim::simulate(scene, o);
  EXPECT_GT(count(r, BeamOutcome::Person), 100u);
  EXPECT_EQ(count(r, BeamOutcome::GlassDirect) + count(r, BeamOutcome::GlassTransmitted), 0u);
}

TEST(Simulator, TrajectoryFollowsTheWaypoints) {
  const sim::Scene scene = sim::loadScene(kMaps / "paper-corridor" / "scene.yaml");
  const sim::SimResult r = sim::simulate(scene, {1});
  ASSERT_FALSE(r.ground_truth.empty());
  EXPECT_LT((r.ground_truth.front().pose.t - Vec2(1, 1)).norm(), 1e-9);
  EXPECT_LT((r.ground_truth.back().pose.t - Vec2(2, 1)).norm(), 0.06);
  double path = 0;
  for (std::size_t k = 1; k < r.ground_truth.size(); ++k)
    path += (r.ground_truth[k].pose.t - r.ground_truth[k - 1].pose.t).norm();
  EXPECT_NEAR(path, 22 + 12 + 12 + 21, 0.1);
  // Laser poses as a SLAM would give them: near the truth.
  for (std::size_t k = 0; k < r.ground_truth.size(); ++k)
    EXPECT_LT((r.log.scans[k].laser_pose.t - r.ground_truth[k].pose.t).norm(), 0.08);
}

TEST(Simulator, OdometryBiasStretchesThePath) {
  sim::Scene scene = sim::loadScene(kMaps / "glass-corridor" / "scene.yaml");
  scene.motion.odom_scale_bias = 0.05;
  scene.motion.odom_trans_sigma = 0.0;
  const sim::SimResult r = sim::simulate(scene, {2});
  double truth = 0, odom = 0;
  for (std::size_t k = 1; k < r.ground_truth.size(); ++k) {
    truth += (r.ground_truth[k].pose.t - r.ground_truth[k - 1].pose.t).norm();
    odom += (r.log.odometry[k].pose.t - r.log.odometry[k - 1].pose.t).norm();
  }
  EXPECT_NEAR(odom / truth, 1.05, 1e-6);
}

TEST(Simulator, WrittenLogReadsBackEqual) {
  const sim::Scene scene = sim::loadScene(kMaps / "office-floor" / "scene.yaml");
  sim::SimOptions o;
  o.duration_limit = 2.0;
  const sim::SimResult r = sim::simulate(scene, o);
  const fs::path dir = fs::temp_directory_path() / "glassmap_test_sim_log";
  fs::create_directories(dir);
  writeCarmenLog(dir / "log.clf", r.log);
  const LaserLog back = readCarmenLog(dir / "log.clf");
  ASSERT_EQ(back.scans.size(), r.log.scans.size());
  for (std::size_t k = 0; k < back.scans.size(); ++k) {
    const LaserScan& a = r.log.scans[k];
    const LaserScan& b = back.scans[k];
    ASSERT_EQ(a.ranges.size(), b.ranges.size());
    EXPECT_NEAR(a.timestamp, b.timestamp, 1e-6);
    EXPECT_NEAR(a.start_angle, b.start_angle, 1e-6);
    EXPECT_NEAR(a.angular_step, b.angular_step, 1e-6);
    EXPECT_TRUE(approxEqual(a.laser_pose, b.laser_pose, 1e-5, 1e-5));
    EXPECT_TRUE(approxEqual(a.odom_pose, b.odom_pose, 1e-5, 1e-5));
    for (std::size_t i = 0; i < a.ranges.size(); ++i) ASSERT_NEAR(a.ranges[i], b.ranges[i], 1e-3);
  }
  fs::remove_all(dir);
}

TEST(Scene, BadScenesGiveClearErrors) {
  const fs::path dir = fs::temp_directory_path() / "glassmap_test_scene";
  fs::create_directories(dir);
  std::ofstream(dir / "bad.yaml") << "name: x\nfloorplan: missing.geojson\n";
  EXPECT_THROW(sim::loadScene(dir / "bad.yaml"), Error);
  std::ofstream(dir / "bad2.yaml") << "name: [unclosed\n";
  try {
    sim::loadScene(dir / "bad2.yaml");
    ADD_FAILURE() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("bad2.yaml"), std::string::npos);
  }
  EXPECT_THROW(sim::laserPreset("lidar-9000"), Error);
  fs::remove_all(dir);
}

TEST(Scene, ALaserMountPutsTheLaserOffTheTurningAxis) {
  const fs::path dir = fs::temp_directory_path() / "glassmap_test_scene_mount";
  fs::create_directories(dir);
  fs::copy_file(kMaps / "paper-corridor/floorplan.geojson", dir / "floorplan.geojson",
                fs::copy_options::overwrite_existing);
  const std::string head = "name: m\nfloorplan: floorplan.geojson\ntrajectory: {waypoints: [[1, 1], [5, 1]]}\n";
  std::ofstream(dir / "mount.yaml") << head << "laser: {preset: sick-lms200, mount: [0.3, -0.1, 90]}\n";
  const sim::Scene s = sim::loadScene(dir / "mount.yaml");
  EXPECT_TRUE(approxEqual(s.laser.T_base_laser, Pose2(0.3, -0.1, kPi / 2), 1e-12, 1e-12));
  // The log's laser poses are the robot's poses times the mount; its odometry stays the robot's.
  sim::SimOptions o;
  o.duration_limit = 2.0;
  const sim::SimResult r = sim::simulate(s, o);
  ASSERT_FALSE(r.log.scans.empty());
  EXPECT_TRUE(approxEqual(r.ground_truth.front().pose, r.log.scans.front().laser_pose, 0.1, 0.05));
  EXPECT_NEAR(r.log.scans.front().laser_pose.theta - r.log.scans.front().odom_pose.theta, kPi / 2, 0.05);
  std::ofstream(dir / "bad.yaml") << head << "laser: {preset: sick-lms200,\n  mount: [0.3, 0]}\n";
  try {
    sim::loadScene(dir / "bad.yaml");
    ADD_FAILURE() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.yaml"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("laser.mount"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

namespace {

// A straight 26 m corridor, 4 m wide, driven along its axis at 0.5 m/s; a coarse laser at 10 Hz.
sim::Scene corridorScene() {
  sim::Scene s;
  s.name = "kidnap-corridor";
  s.map.segments.push_back({Vec2(-1, -2), Vec2(25, -2), Material::Wall, 0.1});
  s.map.segments.push_back({Vec2(-1, 2), Vec2(25, 2), Material::Wall, 0.1});
  s.map.segments.push_back({Vec2(-1, -2), Vec2(-1, 2), Material::Wall, 0.1});
  s.map.segments.push_back({Vec2(25, -2), Vec2(25, 2), Material::Wall, 0.1});
  s.laser.fov = deg2rad(180.0);
  s.laser.resolution = deg2rad(10.0);
  s.laser.max_range = 30;
  s.laser.rate = 10;
  s.trajectory.waypoints = {Vec2(0, 0), Vec2(24, 0)};
  s.trajectory.round_trip = true;
  s.trajectory.speed = 0.5;
  return s;
}

sim::SimOptions runFor(double seconds, std::uint64_t seed) {
  sim::SimOptions o;
  o.seed = seed;
  o.duration_limit = seconds;
  o.repeat_until_limit = true;
  return o;
}

}  // namespace

TEST(Kidnap, TruthJumpsAheadOdometryRecordsNoMotion) {
  const sim::Scene scene = corridorScene();
  const sim::SimResult plain = sim::simulate(scene, runFor(20.0, 5));
  sim::SimOptions opt = runFor(20.0, 5);
  opt.kidnap.time = 5.0;
  opt.kidnap.along = 3.0;
  const sim::SimResult r = sim::simulate(scene, opt);
  EXPECT_FALSE(plain.kidnap);
  ASSERT_TRUE(r.kidnap);
  const std::size_t k = r.kidnap->scan;
  EXPECT_EQ(k, 50u);
  EXPECT_DOUBLE_EQ(r.kidnap->time, 5.0);
  EXPECT_NEAR(r.kidnap->distance(), 3.0, 1e-9);
  // The run keeps its length; before the kidnapping it is the run without one, draw for draw.
  ASSERT_EQ(r.ground_truth.size(), plain.ground_truth.size());
  for (std::size_t i = 0; i < k; ++i) {
    EXPECT_EQ(r.ground_truth[i].pose.t, plain.ground_truth[i].pose.t) << i;
    EXPECT_EQ(r.log.odometry[i].pose.t, plain.log.odometry[i].pose.t) << i;
    EXPECT_EQ(r.log.scans[i].ranges, plain.log.scans[i].ranges) << i;
  }
  // The truth jumps 3 m (plus one 5 cm step) at scan k ...
  EXPECT_NEAR((r.ground_truth[k].pose.t - r.ground_truth[k - 1].pose.t).norm(), 3.05, 1e-6);
  EXPECT_NEAR(r.ground_truth[k].pose.x(), 5.5, 1e-9);
  // ... the odometry does not move at all for that step ...
  EXPECT_EQ(r.log.odometry[k].pose.t, r.log.odometry[k - 1].pose.t);
  EXPECT_EQ(r.log.odometry[k].pose.theta, r.log.odometry[k - 1].pose.theta);
  EXPECT_EQ(r.log.scans[k].odom_pose.t, r.log.scans[k - 1].odom_pose.t);
  // ... and then integrates the real motion again: it ends about 3 m behind the truth.
  const Vec2 lag = r.ground_truth.back().pose.t - r.log.odometry.back().pose.t;
  EXPECT_NEAR(lag.x(), 3.0, 0.15);
  EXPECT_NEAR(lag.y(), 0.0, 0.15);
  const Pose2 moved_truth = r.ground_truth[k].pose.between(r.ground_truth.back().pose);
  const Pose2 moved_odom = r.log.odometry[k].pose.between(r.log.odometry.back().pose);
  EXPECT_NEAR((moved_truth.t - moved_odom.t).norm(), 0.0, 0.15);
  // The scans after it see the corridor from the new pose: the beam straight ahead (to the end
  // wall at x = 25) is 3 m shorter than in the run without kidnapping.
  const std::size_t ahead = r.log.scans[k].ranges.size() / 2;
  EXPECT_NEAR(plain.log.scans[k].ranges[ahead] - r.log.scans[k].ranges[ahead], 3.0, 0.1);
}

TEST(Kidnap, SameSeedSameRun) {
  sim::SimOptions opt = runFor(12.0, 11);
  opt.kidnap.time = 4.0;
  opt.kidnap.along = 2.0;
  const sim::SimResult a = sim::simulate(corridorScene(), opt);
  const sim::SimResult b = sim::simulate(corridorScene(), opt);
  ASSERT_EQ(a.log.scans.size(), b.log.scans.size());
  for (std::size_t i = 0; i < a.log.scans.size(); ++i) {
    EXPECT_EQ(a.log.scans[i].ranges, b.log.scans[i].ranges);
    EXPECT_EQ(a.log.odometry[i].pose.t, b.log.odometry[i].pose.t);
    EXPECT_EQ(a.ground_truth[i].pose.t, b.ground_truth[i].pose.t);
  }
  opt.seed = 12;
  const sim::SimResult c = sim::simulate(corridorScene(), opt);
  EXPECT_NE(a.log.odometry.back().pose.t, c.log.odometry.back().pose.t);
  EXPECT_EQ(a.kidnap->scan, c.kidnap->scan);  // the event itself does not depend on the seed
}

TEST(Kidnap, JumpToAPoseMovesTheRestRigidly) {
  const sim::Scene scene = corridorScene();
  const sim::SimResult plain = sim::simulate(scene, runFor(20.0, 3));
  sim::SimOptions opt = runFor(20.0, 3);
  opt.kidnap.time = 2.05;  // the first scan at or after it: 2.1 s
  opt.kidnap.to = Pose2(20.0, 1.0, kPi);
  const sim::SimResult r = sim::simulate(scene, opt);
  ASSERT_TRUE(r.kidnap);
  const std::size_t k = r.kidnap->scan;
  EXPECT_EQ(k, 21u);
  EXPECT_NEAR(r.ground_truth[k].pose.x(), 20.0, 1e-9);
  EXPECT_NEAR(r.ground_truth[k].pose.y(), 1.0, 1e-9);
  EXPECT_NEAR(angleDiff(r.ground_truth[k].pose.theta, kPi), 0.0, 1e-9);
  EXPECT_NEAR(r.kidnap->distance(), std::hypot(20.0 - 1.05, 1.0), 1e-9);
  // Same motion in the robot's frame as without kidnapping (now heading -x from x = 20).
  const Pose2 a = plain.ground_truth[k].pose.between(plain.ground_truth[k + 60].pose);
  const Pose2 b = r.ground_truth[k].pose.between(r.ground_truth[k + 60].pose);
  EXPECT_NEAR((a.t - b.t).norm(), 0.0, 1e-9);
  EXPECT_NEAR(r.ground_truth[k + 60].pose.x(), 17.0, 1e-9);
  EXPECT_EQ(r.log.odometry[k].pose.t, r.log.odometry[k - 1].pose.t);
}

TEST(Kidnap, ImpossibleKidnappingsAreRefused) {
  sim::SimOptions opt = runFor(10.0, 1);
  opt.kidnap.time = 0.0;
  EXPECT_THROW(sim::simulate(corridorScene(), opt), Error);
  opt.kidnap.time = 10.5;  // after the run
  EXPECT_THROW(sim::simulate(corridorScene(), opt), Error);
  opt.kidnap.time = 5.0;
  opt.kidnap.along = -1.0;
  EXPECT_THROW(sim::simulate(corridorScene(), opt), Error);
  // A trajectory driven once (48 m there and back) has nothing 60 m ahead.
  sim::SimOptions once;
  once.kidnap.time = 5.0;
  once.kidnap.along = 60.0;
  EXPECT_THROW(sim::simulate(corridorScene(), once), Error);
  // 10 m ahead is fine: the run ends with the trajectory, 10 m (20 s) shorter.
  once.kidnap.along = 10.0;
  const sim::SimResult plain = sim::simulate(corridorScene(), sim::SimOptions{});
  const sim::SimResult r = sim::simulate(corridorScene(), once);
  ASSERT_TRUE(r.kidnap);
  EXPECT_NEAR(static_cast<double>(plain.ground_truth.size() - r.ground_truth.size()), 200.0, 1.0);
}
