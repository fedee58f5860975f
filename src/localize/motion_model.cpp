#include "glassmap/localize/motion_model.hpp"

#include <cmath>

namespace glassmap::localize {

OdometryDelta odometryDelta(const Pose2& from, const Pose2& to) {
  OdometryDelta d;
  const Vec2 step = to.t - from.t;
  d.trans = step.norm();
  d.rot1 = d.trans < 1e-3 ? 0.0 : angleDiff(std::atan2(step.y(), step.x()), from.theta);
  d.rot2 = angleDiff(angleDiff(to.theta, from.theta), d.rot1);
  if (std::abs(d.rot1) > kPi / 2) {  // driving backwards: turn by rot1 - pi, move -trans
    d.rot1 = wrapAngle(d.rot1 - kPi);
    d.rot2 = wrapAngle(d.rot2 + kPi);
    d.trans = -d.trans;
  }
  return d;
}

Pose2 sampleMotionOdometry(const Pose2& x, const OdometryDelta& u, const OdometryNoise& a, std::mt19937_64& rng) {
  std::normal_distribution<double> n01(0.0, 1.0);
  const double r1 = u.rot1 * u.rot1, r2 = u.rot2 * u.rot2, t2 = u.trans * u.trans, t = std::abs(u.trans);
  // Probabilistic Robotics eq. 5.37-5.39 (variances a1 rot^2 + a2 trans^2, a3 trans^2 + a4 rot^2),
  // plus the random walks.
  const double walk_rot = 0.5 * a.walk_heading * t;
  const double rot1 =
      u.rot1 - std::sqrt(a.alpha1 * r1 + a.alpha2 * t2 + a.walk_turn * std::abs(u.rot1) + walk_rot) * n01(rng);
  const double trans = u.trans - std::sqrt(a.alpha3 * t2 + a.alpha4 * (r1 + r2) + a.walk_trans * t) * n01(rng);
  const double rot2 =
      u.rot2 - std::sqrt(a.alpha1 * r2 + a.alpha2 * t2 + a.walk_turn * std::abs(u.rot2) + walk_rot) * n01(rng);
  // eq. 5.40-5.42
  const double heading = x.theta + rot1;
  return {x.t + trans * Vec2(std::cos(heading), std::sin(heading)), heading + rot2};
}

}  // namespace glassmap::localize
