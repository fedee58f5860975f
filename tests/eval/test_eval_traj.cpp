// Trajectory evaluation: timestamp association, ATE statistics as evo computes them, heading
// error, time fraction under a threshold.
#include <gtest/gtest.h>

#include <cmath>

#include "glassmap/core/error.hpp"
#include "glassmap/eval/trajectory.hpp"

namespace glassmap::eval {
namespace {

std::vector<StampedPose> line(int n, double dt = 0.1) {
  std::vector<StampedPose> t;
  for (int i = 0; i < n; ++i) t.push_back({i * dt, Pose2(0.1 * i, 0.0, 0.0), 0, 0});
  return t;
}

TEST(EvalTraj, KnownErrorsGiveKnownStatistics) {
  const auto truth = line(4);
  auto est = truth;
  const double offsets[4] = {0.0, 0.1, 0.3, 0.4};  // sideways errors [m]
  for (int i = 0; i < 4; ++i) est[i].pose.t.y() += offsets[i];
  est[2].pose.theta = deg2rad(10.0);
  const TrajectoryErrors r = evaluateTrajectory(truth, est);
  EXPECT_EQ(r.matched, 4u);
  EXPECT_EQ(r.unmatched, 0u);
  EXPECT_NEAR(r.mean, 0.2, 1e-12);
  EXPECT_NEAR(r.rmse, std::sqrt((0.01 + 0.09 + 0.16) / 4.0), 1e-12);
  EXPECT_NEAR(r.median, 0.2, 1e-12);
  EXPECT_NEAR(r.max, 0.4, 1e-12);
  EXPECT_NEAR(r.min, 0.0, 1e-12);
  EXPECT_NEAR(r.std, std::sqrt((0.04 + 0.01 + 0.01 + 0.04) / 4.0), 1e-12);
  EXPECT_NEAR(r.heading_mean_deg, 2.5, 1e-9);
  EXPECT_NEAR(r.heading_max_deg, 10.0, 1e-9);
  // Errors 0 and 0.1 are under 0.2 m: half of the time (equal intervals).
  EXPECT_NEAR(r.fraction_under, 0.5, 1e-12);
}

TEST(EvalTraj, AssociatesByNearestTimestampWithinTolerance) {
  const auto truth = line(10);
  std::vector<StampedPose> est{{0.304, Pose2(0.3, 0, 0), 0, 0},  // matches t = 0.3
                               {0.596, Pose2(0.6, 0, 0), 0, 0},  // matches t = 0.6
                               {0.55, Pose2(0.0, 0, 0), 0, 0},   // 0.05 s from any truth pose
                               {5.0, Pose2(0.0, 0, 0), 0, 0}};   // after the truth ends
  const TrajectoryErrors r = evaluateTrajectory(truth, est);
  EXPECT_EQ(r.matched, 2u);
  EXPECT_EQ(r.unmatched, 2u);
  EXPECT_NEAR(r.max, 0.0, 1e-9);
  TrajectoryEvalOptions loose;
  loose.max_time_diff = 0.06;
  EXPECT_EQ(evaluateTrajectory(truth, est, loose).matched, 3u);
}

TEST(EvalTraj, HeadingErrorWrapsAround) {
  auto truth = line(2), est = line(2);
  truth[0].pose.theta = deg2rad(179.0);
  est[0].pose.theta = deg2rad(-179.0);
  EXPECT_NEAR(evaluateTrajectory(truth, est).heading_max_deg, 2.0, 1e-9);
}

TEST(EvalTraj, NothingMatchingIsAnError) {
  std::vector<StampedPose> est{{100.0, Pose2(), 0, 0}};
  EXPECT_THROW(evaluateTrajectory(line(3), est), Error);
}

}  // namespace
}  // namespace glassmap::eval
