#pragma once
// Private to sim: the true trajectory sampled at the laser rate, and the noisy odometry on it.

#include <cstdint>
#include <random>
#include <vector>

#include "glassmap/core/pose2.hpp"
#include "glassmap/sim/scene.hpp"

namespace glassmap::sim {

/// True base poses at times k * dt, from turning in place at each waypoint and driving straight.
/// With `limit` > 0 the path is driven back and forth until `limit` seconds, else once.
std::vector<Pose2> sampleTrajectory(const TrajectorySpec& spec, double dt, double limit, bool repeat);

/// Odometry poses: the true increments decomposed into (rot1, trans, rot2), perturbed by
/// Gaussian noise growing with the motion, a scale bias and a heading drift, and integrated.
std::vector<Pose2> simulateOdometry(const std::vector<Pose2>& truth, const MotionNoise& noise,
                                    std::mt19937_64& rng);

}  // namespace glassmap::sim
