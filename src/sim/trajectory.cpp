#include "trajectory.hpp"

#include <cmath>

#include "glassmap/core/error.hpp"

namespace glassmap::sim {
namespace {

struct Keyframe {
  double time;
  Pose2 pose;
};

// Keyframes of one pass over `points`, starting at `start` heading, from time t0.
void appendPass(const std::vector<Vec2>& points, const TrajectorySpec& spec, std::vector<Keyframe>& keys) {
  for (std::size_t i = 1; i < points.size(); ++i) {
    const Pose2 here = keys.back().pose;
    const Vec2 delta = points[i] - here.t;
    const double dist = delta.norm();
    if (dist < 1e-9) continue;
    const double heading = std::atan2(delta.y(), delta.x());
    const double turn = std::abs(angleDiff(heading, here.theta));
    if (turn > 1e-12) keys.push_back({keys.back().time + turn / spec.turn_rate, Pose2(here.t, heading)});
    keys.push_back({keys.back().time + dist / spec.speed, Pose2(points[i], heading)});
  }
}

}  // namespace

std::vector<Pose2> sampleTrajectory(const TrajectorySpec& spec, double dt, double limit, bool repeat) {
  if (spec.waypoints.size() < 2) throw Error("a trajectory needs at least two waypoints");
  std::vector<Vec2> forward = spec.waypoints;
  if (spec.round_trip)
    for (std::size_t i = spec.waypoints.size() - 1; i-- > 0;) forward.push_back(spec.waypoints[i]);
  const Vec2 d0 = forward[1] - forward[0];
  const double h0 = std::isnan(spec.start_heading) ? std::atan2(d0.y(), d0.x()) : spec.start_heading;
  std::vector<Keyframe> keys{{0.0, Pose2(forward[0], h0)}};
  appendPass(forward, spec, keys);
  if (repeat && limit > 0) {
    std::vector<Vec2> backward(forward.rbegin(), forward.rend());
    bool back = true;
    while (keys.back().time < limit) {
      const double before = keys.back().time;
      appendPass(back ? backward : forward, spec, keys);
      if (keys.back().time <= before) break;  // degenerate path
      back = !back;
    }
  }
  const double end = (limit > 0) ? std::min(limit, keys.back().time) : keys.back().time;
  std::vector<Pose2> poses;
  poses.reserve(static_cast<std::size_t>(end / dt) + 2);
  std::size_t k = 0;
  for (std::size_t n = 0;; ++n) {
    const double t = static_cast<double>(n) * dt;
    if (t > end + 1e-9) break;
    while (k + 1 < keys.size() - 1 && keys[k + 1].time < t) ++k;
    const Keyframe& a = keys[k];
    const Keyframe& b = keys[std::min(k + 1, keys.size() - 1)];
    const double span = b.time - a.time;
    const double s = span > 0 ? std::clamp((t - a.time) / span, 0.0, 1.0) : 1.0;
    poses.push_back(Pose2::interpolate(a.pose, b.pose, s));
  }
  return poses;
}

std::size_t applyKidnap(std::vector<Pose2>& truth, double dt, const Kidnap& kidnap,
                        const std::function<std::vector<Pose2>(double)>& resample) {
  if (kidnap.time < 0 || truth.empty()) return 0;
  if (!(kidnap.time > 0) || !std::isfinite(kidnap.time))
    throw Error("the kidnapping time must be a positive number of seconds", {}, 0, "kidnap-at");
  if (!(kidnap.along >= 0) || !std::isfinite(kidnap.along))
    throw Error("the kidnapping distance along the trajectory must be >= 0 m", {}, 0, "kidnap-along");
  const auto k = static_cast<std::size_t>(std::ceil(kidnap.time / dt - 1e-9));
  const std::size_t n = truth.size();
  if (k >= n)
    throw Error("the kidnapping at " + std::to_string(kidnap.time) + " s is after the end of the run (" +
                    std::to_string(static_cast<double>(n - 1) * dt) + " s)",
                {}, 0, "kidnap-at");
  if (kidnap.to) {
    // The rest of the trajectory, moved rigidly so that it starts at the new pose.
    const Pose2 T_new_old = *kidnap.to * truth[k].inverse();
    for (std::size_t j = k; j < n; ++j) truth[j] = T_new_old * truth[j];
    return k;
  }
  // Skip ahead: drop the poses from k up to the first one `along` metres further along the path.
  std::vector<Pose2> path = truth;
  double horizon = std::max(static_cast<double>(n - 1) * dt, dt);
  for (;;) {
    double length = 0.0;
    std::size_t m = k;
    while (m + 1 < path.size() && length < kidnap.along) {
      length += (path[m + 1].t - path[m].t).norm();
      ++m;
    }
    const bool reached = length >= kidnap.along;
    if (reached && path.size() - m >= n - k) {
      truth.resize(k);
      truth.insert(truth.end(), path.begin() + static_cast<std::ptrdiff_t>(m),
                   path.begin() + static_cast<std::ptrdiff_t>(m + (n - k)));
      return k;
    }
    horizon *= 2.0;
    std::vector<Pose2> longer = resample(horizon);
    if (longer.size() <= path.size()) {
      // Driven once: the run ends with the trajectory, shorter by the part skipped.
      if (!reached)
        throw Error("the kidnapping skips " + std::to_string(kidnap.along) + " m ahead, past the end of the trajectory",
                    {}, 0, "kidnap-along");
      truth.resize(k);
      truth.insert(truth.end(), path.begin() + static_cast<std::ptrdiff_t>(m), path.end());
      return k;
    }
    path = std::move(longer);
  }
}

std::vector<Pose2> simulateOdometry(const std::vector<Pose2>& truth, const MotionNoise& noise, std::mt19937_64& rng,
                                    std::size_t teleport) {
  std::vector<Pose2> odom;
  odom.reserve(truth.size());
  if (truth.empty()) return odom;
  std::normal_distribution<double> gauss(0.0, 1.0);
  odom.push_back(truth.front());
  for (std::size_t k = 1; k < truth.size(); ++k) {
    // A kidnapping moves the robot without its wheels: no motion at all for that step.
    const bool carried = k == teleport;
    const Vec2 d = carried ? Vec2::Zero() : Vec2(truth[k].t - truth[k - 1].t);
    const double trans = d.norm();
    // Decomposition of Probabilistic Robotics' odometry model (rot1, trans, rot2).
    const double rot1 = trans > 1e-9 ? angleDiff(std::atan2(d.y(), d.x()), truth[k - 1].theta) : 0.0;
    const double rot2 = carried ? 0.0 : angleDiff(angleDiff(truth[k].theta, truth[k - 1].theta), rot1);
    // Random-walk noise: variances grow linearly with the motion, so the error after a path
    // does not depend on the sampling rate.
    const double s_trans = noise.odom_trans_sigma * std::sqrt(trans);
    const double s_rot1 =
        std::hypot(noise.odom_rot_sigma * std::sqrt(std::abs(rot1)), noise.odom_rot_per_m * std::sqrt(trans / 2));
    const double s_rot2 =
        std::hypot(noise.odom_rot_sigma * std::sqrt(std::abs(rot2)), noise.odom_rot_per_m * std::sqrt(trans / 2));
    const double n_trans = trans * (1.0 + noise.odom_scale_bias) + s_trans * gauss(rng);
    const double n_rot1 = rot1 + s_rot1 * gauss(rng);
    const double n_rot2 = rot2 + s_rot2 * gauss(rng) + noise.odom_drift_per_m * trans;
    const Pose2& p = odom.back();
    const double heading = p.theta + n_rot1;
    odom.emplace_back(p.t + n_trans * Vec2(std::cos(heading), std::sin(heading)), heading + n_rot2);
  }
  return odom;
}

}  // namespace glassmap::sim
