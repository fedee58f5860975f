#pragma once
// Private to sim: the true trajectory sampled at the laser rate, and the noisy odometry on it.

#include <cstdint>
#include <functional>
#include <random>
#include <vector>

#include "glassmap/core/pose2.hpp"
#include "glassmap/sim/scene.hpp"
#include "glassmap/sim/simulator.hpp"

namespace glassmap::sim {

/// True base poses at times k * dt, from turning in place at each waypoint and driving straight.
/// With `limit` > 0 the path is driven back and forth until `limit` seconds, else once.
std::vector<Pose2> sampleTrajectory(const TrajectorySpec& spec, double dt, double limit, bool repeat);

/// Odometry poses: the true increments decomposed into (rot1, trans, rot2), perturbed by
/// Gaussian noise growing with the motion, a scale bias and a heading drift, and integrated.
/// The step into truth[teleport] (0 = none) is a kidnapping: no motion is recorded for it. The
/// random draws do not depend on it, so the odometry before a kidnapping equals a run without one.
std::vector<Pose2> simulateOdometry(const std::vector<Pose2>& truth, const MotionNoise& noise, std::mt19937_64& rng,
                                    std::size_t teleport = 0);

/// Applies a kidnapping to true poses sampled every dt: returns the index of the first pose after
/// the jump, and edits `truth` (rigid move of the rest, or a skip ahead along it). `resample(s)`
/// must return the trajectory sampled over s seconds (longer than truth) for a skip that needs more
/// path; it returns fewer poses when the trajectory is driven once.
std::size_t applyKidnap(std::vector<Pose2>& truth, double dt, const Kidnap& kidnap,
                        const std::function<std::vector<Pose2>(double)>& resample);

}  // namespace glassmap::sim
