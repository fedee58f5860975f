// visiblePart: a 10 m x 4 m box split at x = 5 by a wall with a glass pane (y = 1 .. 3), seen from
// (2, 2). Through the pane the whole right wall is in sight, and the floor and ceiling walls of the
// right room from x = 8 on (the lines through the pane's ends); everything of the left room is.
#include <gtest/gtest.h>

#include <cmath>

#include "glassmap/core/angles.hpp"
#include "glassmap/eval/visibility.hpp"

namespace glassmap::eval {
namespace {

VectorMap box() {
  VectorMap m;
  auto add = [&](Vec2 a, Vec2 b, Material mat) { m.add(a, b, mat); };
  add({0, 0}, {10, 0}, Material::Wall);
  add({10, 0}, {10, 4}, Material::Wall);
  add({10, 4}, {0, 4}, Material::Wall);
  add({0, 4}, {0, 0}, Material::Wall);
  add({5, 0}, {5, 1}, Material::Wall);
  add({5, 1}, {5, 3}, Material::Glass);
  add({5, 3}, {5, 4}, Material::Wall);
  return m;
}

double length(const VectorMap& m, Material mat) {
  double l = 0;
  for (const MapSegment& s : m.segments)
    if (s.material == mat) l += s.length();
  return l;
}

TEST(Visibility, GlassIsSeeThroughAndWallsOcclude) {
  Viewpoint v;
  v.pose = Pose2(2, 2, 0);
  v.start_angle = -kPi;
  v.span = 2 * kPi;
  v.max_range = 30;
  const VectorMap seen = visiblePart(box(), {v});
  // Left room: 5 + 5 + 4, divider 2 of wall; right room: 4 + 2 + 2. Glass: the pane, 2.
  EXPECT_NEAR(length(seen, Material::Wall), 24.0, 0.1);
  EXPECT_NEAR(length(seen, Material::Glass), 2.0, 0.05);
  // The floor of the right room is seen from x = 8 on, not before.
  for (const MapSegment& s : seen.segments)
    if (std::abs(s.a.y()) < 1e-9 && std::abs(s.b.y()) < 1e-9 && std::min(s.a.x(), s.b.x()) > 5.0) {
      EXPECT_NEAR(std::min(s.a.x(), s.b.x()), 8.0, 0.05);
    }
}

TEST(Visibility, FieldOfViewAndRangeLimitTheView) {
  Viewpoint v;
  v.pose = Pose2(2, 2, 0);
  v.start_angle = -kPi / 4;  // 90 degrees facing +x
  v.span = kPi / 2;
  v.max_range = 30;
  const VectorMap ahead = visiblePart(box(), {v});
  // The left wall is behind the sensor; the floor is seen from x = 4 (45 degrees down) to 5.
  for (const MapSegment& s : ahead.segments) EXPECT_GT(std::min(s.a.x(), s.b.x()), 3.9);
  v.max_range = 1.0;
  EXPECT_TRUE(visiblePart(box(), {v}).segments.empty());
  EXPECT_TRUE(visiblePart(box(), {}).segments.empty());
}

TEST(Visibility, ViewpointsOfALogAreThinnedByDistanceAndTurn) {
  LaserLog log;
  for (int i = 0; i < 100; ++i) {
    LaserScan scan;
    scan.laser_pose = Pose2(0.01 * i, 0, i < 50 ? 0.0 : deg2rad(30.0));
    scan.start_angle = -kPi / 2;
    scan.angular_step = deg2rad(1.0);
    scan.max_range = 80;
    scan.ranges.assign(181, 1.0f);
    log.scans.push_back(scan);
  }
  const auto views = viewpointsOfLog(log, 0.25, 30.0);
  // Every 25 poses along x, plus the turn at pose 50: 0, 25, 50, 75.
  ASSERT_EQ(views.size(), 4u);
  EXPECT_DOUBLE_EQ(views[0].max_range, 30.0);
  EXPECT_NEAR(views[0].span, kPi, 1e-9);
  EXPECT_NEAR(views[2].pose.theta, deg2rad(30.0), 1e-12);
}

}  // namespace
}  // namespace glassmap::eval
