#include <gtest/gtest.h>

#include <cmath>

#include "glassmap/core/angles.hpp"
#include "glassmap/io/ros2_tf.hpp"

namespace glassmap::ros2 {
namespace {

TEST(Ros2Tf, InterpolatesLinearlyAndByTheShortestAngle) {
  TfBuffer tf(0.05);
  tf.add("odom", "base", 10.0, Pose2(0.0, 0.0, deg2rad(170.0)), false);
  tf.add("odom", "base", 11.0, Pose2(2.0, -4.0, deg2rad(-170.0)), false);
  const auto mid = tf.lookup("odom", "base", 10.25);
  ASSERT_TRUE(mid);
  EXPECT_NEAR(mid->x(), 0.5, 1e-12);
  EXPECT_NEAR(mid->y(), -1.0, 1e-12);
  EXPECT_NEAR(angleDiff(mid->theta, deg2rad(175.0)), 0.0, 1e-12);  // through 180, not through 0
  const auto exact = tf.lookup("odom", "base", 11.0);
  ASSERT_TRUE(exact);
  EXPECT_TRUE(approxEqual(*exact, Pose2(2.0, -4.0, deg2rad(-170.0)), 1e-15, 1e-15));
  // inverse direction
  const auto inv = tf.lookup("base", "odom", 10.25);
  ASSERT_TRUE(inv);
  EXPECT_TRUE(approxEqual(*inv, mid->inverse(), 1e-12, 1e-12));
}

TEST(Ros2Tf, OutOfOrderSamplesAreSorted) {
  TfBuffer tf;
  tf.add("odom", "base", 2.0, Pose2(2.0, 0.0, 0.0), false);
  tf.add("odom", "base", 0.0, Pose2(0.0, 0.0, 0.0), false);
  tf.add("odom", "base", 1.0, Pose2(1.0, 0.0, 0.0), false);
  EXPECT_NEAR(tf.lookup("odom", "base", 1.5)->x(), 1.5, 1e-12);
  EXPECT_NEAR(tf.lookup("odom", "base", 0.5)->x(), 0.5, 1e-12);
}

TEST(Ros2Tf, ChainThroughStaticAndDynamicEdges) {
  TfBuffer tf(0.1);
  tf.add("base_link", "laser", 0.0, Pose2(0.2, 0.0, kPi), true);  // static: stamp irrelevant
  tf.add("map", "odom", 5.0, Pose2(1.0, 1.0, kPi / 2), false);
  tf.add("map", "odom", 7.0, Pose2(1.0, 1.0, kPi / 2), false);
  tf.add("odom", "base_link", 5.0, Pose2(0.0, 0.0, 0.0), false);
  tf.add("odom", "base_link", 7.0, Pose2(2.0, 0.0, 0.0), false);
  const auto T = tf.lookup("map", "laser", 6.0);
  ASSERT_TRUE(T);
  const Pose2 want = Pose2(1.0, 1.0, kPi / 2) * Pose2(1.0, 0.0, 0.0) * Pose2(0.2, 0.0, kPi);
  EXPECT_TRUE(approxEqual(*T, want, 1e-12, 1e-12));
  // between two children of one parent
  const auto Tl = tf.lookup("laser", "odom", 6.0);
  ASSERT_TRUE(Tl);
  EXPECT_TRUE(approxEqual(*Tl, (Pose2(1.0, 0.0, 0.0) * Pose2(0.2, 0.0, kPi)).inverse(), 1e-12, 1e-12));
  // the static edge alone holds at any time
  EXPECT_TRUE(tf.lookup("base_link", "laser", -1e6));
  EXPECT_TRUE(tf.connected("map", "laser"));
  EXPECT_FALSE(tf.connected("map", "camera"));
  EXPECT_FALSE(tf.lookup("map", "camera", 6.0));
  EXPECT_TRUE(tf.hasEdge("odom", "base_link"));
  EXPECT_EQ(tf.parentOf("odom"), "map");
  EXPECT_EQ(tf.edges().size(), 3u);
}

TEST(Ros2Tf, ExtrapolationBeyondToleranceGivesNothing) {
  TfBuffer tf(0.1);
  tf.add("odom", "base", 1.0, Pose2(1.0, 0.0, 0.0), false);
  tf.add("odom", "base", 2.0, Pose2(2.0, 0.0, 0.0), false);
  EXPECT_FALSE(tf.lookup("odom", "base", 0.85));
  EXPECT_FALSE(tf.lookup("odom", "base", 2.15));
  const auto held = tf.lookup("odom", "base", 2.05);  // within tolerance: held at the last sample
  ASSERT_TRUE(held);
  EXPECT_EQ(held->x(), 2.0);
  EXPECT_TRUE(tf.lookup("odom", "base", 2.5, 1.0));  // per-lookup tolerance
}

TEST(Ros2Tf, MessagesAreProjectedAndTiltCounted) {
  TFMessageMsg m;
  TransformStampedMsg t;
  t.header.stamp = {3, 500000000};
  t.header.frame_id = "odom";
  t.child_frame_id = "base";
  t.translation = {1.0, 2.0, 0.7};
  // yaw 30 deg, then 20 deg of roll
  const double cy = std::cos(deg2rad(15.0)), sy = std::sin(deg2rad(15.0));
  const double cr = std::cos(deg2rad(10.0)), sr = std::sin(deg2rad(10.0));
  t.rotation = {cy * sr, sy * sr, sy * cr, cy * cr};  // q_yaw * q_roll
  m.transforms.push_back(t);
  TransformStampedMsg bad = t;
  bad.child_frame_id = "x";
  bad.rotation = {0, 0, 0, 0};
  m.transforms.push_back(bad);
  TfBuffer tf;
  tf.add(m, false);
  EXPECT_EQ(tf.invalid(), 1u);
  EXPECT_EQ(tf.tilted(), 1u);
  EXPECT_NEAR(rad2deg(tf.maxTilt()), 20.0, 1e-9);
  const auto p = tf.lookup("odom", "base", 3.5);
  ASSERT_TRUE(p);
  EXPECT_NEAR(rad2deg(p->theta), 30.0, 1e-9);
  EXPECT_EQ(p->y(), 2.0);
  EXPECT_NEAR(quaternionYaw(yawQuaternion(-2.5)), -2.5, 1e-15);
}

TEST(Ros2Tf, ReparentedChildKeepsTheNewestParent) {
  TfBuffer tf;
  tf.add("odom", "base", 0.0, Pose2(), false);
  tf.add("map", "base", 1.0, Pose2(), false);
  EXPECT_EQ(tf.parentOf("base"), "map");
  EXPECT_EQ(tf.reparented(), 1u);
}

}  // namespace
}  // namespace glassmap::ros2
