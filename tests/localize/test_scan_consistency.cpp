// The scans against each other (ScanConsistency) and the guard it gives the particle filter: a
// kidnapped robot's scans break, a robot whose scans are explained better elsewhere for a while
// (clutter lined up with other walls) keeps its tracked estimate.
#include <gtest/gtest.h>

#include <cmath>
#include <utility>

#include "glassmap/geometry/ray_caster.hpp"
#include "glassmap/localize/particle_filter.hpp"
#include "glassmap/localize/scan_consistency.hpp"

namespace glassmap::localize {
namespace {

void addSegment(VectorMap& m, Vec2 a, Vec2 b) {
  MapSegment s;
  s.a = a;
  s.b = b;
  m.segments.push_back(s);
}

// A 10 x 6 m room with a short L-shaped wall at (6..8, 2..3.5): no symmetry.
VectorMap room() {
  VectorMap m;
  addSegment(m, {0, 0}, {10, 0});
  addSegment(m, {10, 0}, {10, 6});
  addSegment(m, {10, 6}, {0, 6});
  addSegment(m, {0, 6}, {0, 0});
  addSegment(m, {6, 2}, {8, 2});
  addSegment(m, {8, 2}, {8, 3.5});
  return m;
}

// Two 15 x 6 m rooms joined by a door, the plan the same under half a turn about its centre (15, 3)
// but for two long shelves along the left room. In the world the right room has the shelves' twins
// as furniture, which hide its walls: seen from the right room the scans are those of the twin pose
// in the left room, where the plan explains them (the furniture lines up with the shelves) far
// better than at the true pose (Freiburg 079's cluttered room, docs/localization.md).
VectorMap twoRooms(bool furnished) {
  VectorMap m;
  addSegment(m, {0, 0}, {30, 0});
  addSegment(m, {30, 0}, {30, 6});
  addSegment(m, {30, 6}, {0, 6});
  addSegment(m, {0, 6}, {0, 0});
  addSegment(m, {15, 0}, {15, 2.5});  // the door: y in (2.5, 3.5)
  addSegment(m, {15, 3.5}, {15, 6});
  const std::pair<Vec2, Vec2> shelves[2] = {{{2, 1.2}, {13, 1.2}}, {{3, 4.6}, {12, 4.6}}};
  for (const auto& [a, b] : shelves) {
    addSegment(m, a, b);
    if (furnished) addSegment(m, Vec2(30, 6) - a, Vec2(30, 6) - b);
  }
  return m;
}

Pose2 twin(const Pose2& x) { return Pose2(Vec2(30, 6) - x.t, x.theta + kPi); }

// A 270 deg, 1 deg scan of `world` from `pose`, `beams` of them kept (0 = all).
sensor::BeamSet scanIn(const VectorMap& world, const Pose2& pose, int beams = 0) {
  LaserScan s;
  s.start_angle = -deg2rad(135);
  s.angular_step = deg2rad(1.0);
  s.max_range = 30;
  s.ranges.resize(271);
  const RayCaster caster(world);
  for (std::size_t i = 0; i < s.ranges.size(); ++i) {
    const double a = pose.theta + s.beamAngle(i);
    const double r = caster.castRange(pose.t, Vec2(std::cos(a), std::sin(a)), 30.0);
    s.ranges[i] = std::isfinite(r) ? static_cast<float>(r) : 30.0f;
  }
  return sensor::makeBeamSet(s, beams);
}

// Boxes the floorplan does not have: furniture along the robot's way.
VectorMap clutteredRoom() {
  VectorMap m = room();
  for (const Vec2& c : {Vec2(3.0, 2.6), Vec2(4.6, 0.5), Vec2(1.2, 3.8), Vec2(5.2, 4.4)}) {
    addSegment(m, c + Vec2(-0.3, -0.2), c + Vec2(0.3, -0.2));
    addSegment(m, c + Vec2(0.3, -0.2), c + Vec2(0.3, 0.2));
    addSegment(m, c + Vec2(0.3, 0.2), c + Vec2(-0.3, 0.2));
    addSegment(m, c + Vec2(-0.3, 0.2), c + Vec2(-0.3, -0.2));
  }
  return m;
}

TEST(ScanConsistency, ScansThatAgreeWithTheOdometryDoNotBreak) {
  // Driving a circle through the furniture, whole scans and 15 of their beams.
  const VectorMap world = clutteredRoom();
  for (const int beams : {0, 15}) {
    ScanConsistency c;
    Pose2 x(2.0, 1.5, 0.3);
    ASSERT_EQ(c.add(scanIn(world, x, beams), x).compared, 0u);  // nothing to compare with yet
    for (int k = 0; k < 60; ++k) {
      x = x * Pose2(0.05, 0, 0.03);
      const ScanConsistencyResult r = c.add(scanIn(world, x, beams), x);
      EXPECT_GE(r.compared, beams == 0 ? 300u : 20u) << k;
      EXPECT_LT(r.share, beams == 0 ? 0.05 : 0.15) << beams << " " << k;  // sparse: neighbours 19 deg apart
      EXPECT_FALSE(r.broke) << beams << " " << k;
    }
  }
}

TEST(ScanConsistency, AKidnapOrAnOdometryJumpBreaks) {
  const VectorMap world = clutteredRoom();
  const Pose2 from(2.0, 1.5, 0.3);
  for (const int beams : {0, 15}) {
    // Carried 1.3-2.9 m away while the odometry says 5 cm straight on.
    for (const Pose2& to : {Pose2(4.8, 4.1, 2.4), Pose2(4.0, 2.3, 0.5), Pose2(5.1, 2.7, 1.4), Pose2(3.3, 0.9, 0.6)}) {
      const ScanConsistencyResult r =
          compareScans(scanIn(world, from, beams), from, scanIn(world, to, beams), from * Pose2(0.05, 0, 0), {});
      EXPECT_TRUE(r.broke) << beams << ": " << to.x() << ", " << to.y() << " share " << r.share;
    }
    // The odometry says 1 m ahead and 20 deg left; the robot stood still.
    const ScanConsistencyResult r =
        compareScans(scanIn(world, from, beams), from, scanIn(world, from, beams), from * Pose2(1.0, 0, 0.35), {});
    EXPECT_TRUE(r.broke) << beams << " share " << r.share;
  }
}

// Drives `steps` of 5 cm along y = 2.7 from x = 11 through the door (at step 80) into the right room
// (furnished or not) while the filter tracks it in the plan from the true start; at step `kidnap_at` (0 = never) the
// robot is carried to (22, 1.5, pi) without odometry.
struct GuardRun {
  double error = 0.0;  // position error at the end [m]
  Pose2 estimate, truth;
  std::size_t relocalizations = 0, breaks = 0, probes = 0;
};
GuardRun guardRun(bool furnished, int steps, double doubt_after_m, int kidnap_at = 0) {
  const auto model = sensor::makeSensorModel("glass", twoRooms(false));
  const VectorMap world = twoRooms(furnished);
  FilterOptions o;
  o.max_particles = 2000;
  o.seed = 3;
  o.doubt_after_m = doubt_after_m;
  ParticleFilter f(*model, o);
  Pose2 truth(11.0, 2.7, 0.0);
  f.initialize(truth, 0.05, 0.02);
  f.correct(scanIn(world, truth, 30), nullptr);
  for (int k = 1; k <= steps; ++k) {
    const Pose2 next = truth * Pose2(0.05, 0, 0);
    f.predict(odometryDelta(truth, next));
    truth = k == kidnap_at ? Pose2(22.0, 1.5, kPi) : next;
    const sensor::BeamSet whole = scanIn(world, truth);
    f.correct(scanIn(world, truth, 30), &whole);
  }
  return {(f.estimate().t - truth.t).norm(), f.estimate(), truth, f.relocalizations(), f.breaks(), f.probes()};
}

TEST(ParticleFilter, KeepsItsEstimateWhileTheScansAgreeWithTheOdometry) {
  // In the furnished right room the twin pose explains the scans better than the true one: a
  // probe finds it. Over 2.5 m into the room the scans agree with the odometry: it may not lead.
  const GuardRun guarded = guardRun(true, 130, 4.0);
  EXPECT_GE(guarded.probes, 1u);
  EXPECT_EQ(guarded.breaks, 0u);
  EXPECT_EQ(guarded.relocalizations, 0u);
  EXPECT_LT(guarded.error, 0.1);
  // Without the guard the twin takes over ...
  const GuardRun unguarded = guardRun(true, 130, 0.0);
  EXPECT_GE(unguarded.relocalizations, 1u);
  EXPECT_LT((unguarded.estimate.t - twin(unguarded.truth).t).norm(), 0.2);
  // ... and with it once it has out-explained the tracked estimate over doubt_after_m: an estimate
  // that stays worse than a rival place for metres is given up, break or not.
  const GuardRun later = guardRun(true, 280, 4.0);
  EXPECT_GE(later.relocalizations, 1u);
  EXPECT_LT((later.estimate.t - twin(later.truth).t).norm(), 0.2);
}

TEST(ParticleFilter, AKidnapBreaksTheScansAndThePlaceLeadsAtOnce) {
  // Carried 6 m back into the right room after 5 m: the break licenses the probe, which finds the
  // robot within 2.5 m of driving, before the long doubt (4 m) would have.
  const GuardRun r = guardRun(false, 150, 4.0, 100);
  EXPECT_GE(r.breaks, 1u);
  EXPECT_GE(r.relocalizations, 1u);
  EXPECT_LT(r.error, 0.1);
}

}  // namespace
}  // namespace glassmap::localize
