// rayConsistency: hand-built readings in a 10 m x 4 m box split at x = 5 by a wall with a glass
// pane (y = 1 .. 3), seen from (2, 2): readings at the walls, at the pane and behind it are
// explained; a reading short of every surface is "short", one beyond a wall "through wall".
#include <gtest/gtest.h>

#include <cmath>

#include "glassmap/core/angles.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/eval/consistency.hpp"

namespace glassmap::eval {
namespace {

VectorMap box() {
  VectorMap m;
  m.add({0, 0}, {10, 0}, Material::Wall);
  m.add({10, 0}, {10, 4}, Material::Wall);
  m.add({10, 4}, {0, 4}, Material::Wall);
  m.add({0, 4}, {0, 0}, Material::Wall);
  m.add({5, 0}, {5, 1}, Material::Wall);
  m.add({5, 1}, {5, 3}, Material::Glass);
  m.add({5, 3}, {5, 4}, Material::Wall);
  return m;
}

// One scan at (2, 2) with beams along +x, +y, -x, -y (step 90 deg) and the given ranges.
LaserLog logWith(float east, float north, float west, float south) {
  LaserLog log;
  LaserScan s;
  s.start_angle = 0.0;
  s.angular_step = kPi / 2;
  s.max_range = 30.0;
  s.ranges = {east, north, west, south};
  s.laser_pose = Pose2(2, 2, 0);
  log.scans.push_back(s);
  return log;
}

TEST(RayConsistency, ExplainsWallsPaneAndWhatLiesBehindIt) {
  const VectorMap plan = box();
  // East at the pane (3 m), north wall (2 m), west wall (2 m), south wall (2 m).
  ConsistencyResult r = rayConsistency(logWith(3.0f, 2.0f, 2.05f, 1.95f), plan);
  EXPECT_EQ(r.returns, 4u);
  EXPECT_EQ(r.explained, 4u);
  EXPECT_EQ(r.at_glass, 1u);
  EXPECT_DOUBLE_EQ(r.explained_share, 1.0);
  // East through the pane to the far wall (8 m): explained, not at glass.
  r = rayConsistency(logWith(8.0f, 2.0f, 2.0f, 2.0f), plan);
  EXPECT_EQ(r.explained, 4u);
  EXPECT_EQ(r.at_glass, 0u);
  EXPECT_EQ(r.wall_segments, 6u);
  EXPECT_EQ(r.glass_segments, 1u);
  EXPECT_NEAR(r.wall_length, 2 * 10 + 2 * 4 + 2, 1e-12);
  EXPECT_NEAR(r.glass_length, 2.0, 1e-12);
}

TEST(RayConsistency, ShortAndThroughWallReadingsAreNamed) {
  const VectorMap plan = box();
  // East 1.5 m (clutter in the room), north 2.5 m (0.5 m beyond the wall), west 2.0 (wall),
  // south 2.15 m (0.15 m beyond: outside the 0.10 m tolerance).
  ConsistencyResult r = rayConsistency(logWith(1.5f, 2.5f, 2.0f, 2.15f), plan);
  EXPECT_EQ(r.returns, 4u);
  EXPECT_EQ(r.explained, 1u);
  EXPECT_EQ(r.short_of_plan, 1u);
  EXPECT_EQ(r.through_wall, 2u);
  EXPECT_DOUBLE_EQ(r.explained_share, 0.25);
  // A wider tolerance takes the 0.15 m one in.
  ConsistencyOptions wide;
  wide.tolerance = 0.2;
  r = rayConsistency(logWith(1.5f, 2.5f, 2.0f, 2.15f), plan, wide);
  EXPECT_EQ(r.explained, 2u);
}

TEST(RayConsistency, NearSegmentReadingForgivesWhatTheBeamCrossedFirst) {
  VectorMap plan = box();
  plan.add({3, 1.5}, {3, 2.5}, Material::Wall);  // a cabinet face 1 m east of the pose
  // East 3.0 m: at the pane, but the cabinet face stands before it: first surface says "through a
  // wall", the end point lies on the pane. North 2.05: near the wall either way. West 1.5: in the
  // middle of the room, near nothing. South 1.0: short, near nothing.
  const ConsistencyResult r = rayConsistency(logWith(3.0f, 2.05f, 1.5f, 1.0f), plan);
  EXPECT_EQ(r.explained, 1u);
  EXPECT_EQ(r.through_wall, 1u);
  EXPECT_EQ(r.near_segment, 2u);
  EXPECT_DOUBLE_EQ(r.near_share, 0.5);
  // A reading at the cabinet (1.0 m east) is explained and near.
  const ConsistencyResult at = rayConsistency(logWith(1.0f, 2.0f, 2.0f, 2.0f), plan);
  EXPECT_EQ(at.explained, 4u);
  EXPECT_EQ(at.near_segment, 4u);
}

TEST(RayConsistency, RangeWindowAndNoReturnsAreNotScored) {
  const VectorMap plan = box();
  ConsistencyOptions o;
  o.max_range = 2.5;  // the 3 m pane reading is out of the window
  ConsistencyResult r = rayConsistency(logWith(3.0f, kNoReturn, 0.01f, 2.0f), plan, o);
  EXPECT_EQ(r.returns, 1u);  // south only: no-return and dead-zone readings are skipped too
  EXPECT_EQ(r.explained, 1u);
  // No scans, no returns: share 0, no division by zero.
  r = rayConsistency(LaserLog{}, plan);
  EXPECT_EQ(r.returns, 0u);
  EXPECT_EQ(r.explained_share, 0.0);
  o.tolerance = 0.0;
  EXPECT_THROW(rayConsistency(logWith(3, 2, 2, 2), plan, o), Error);
}

TEST(RayConsistency, MaxScansSpreadsOverTheLog) {
  LaserLog log = logWith(3.0f, 2.0f, 2.0f, 2.0f);
  for (int k = 0; k < 9; ++k) log.scans.push_back(log.scans.front());
  log.scans[5].ranges = {1.0f, 1.0f, 1.0f, 1.0f};  // all short
  ConsistencyOptions o;
  o.max_scans = 2;  // scans 0 and 5
  const ConsistencyResult r = rayConsistency(log, box(), o);
  EXPECT_EQ(r.scans, 2u);
  EXPECT_EQ(r.returns, 8u);
  EXPECT_EQ(r.explained, 4u);
  EXPECT_EQ(r.short_of_plan, 4u);
}

}  // namespace
}  // namespace glassmap::eval
