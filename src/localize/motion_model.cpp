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

MotionSpread motionSpread(const OdometryDelta& u, const OdometryNoise& a) {
  const double r1 = u.rot1 * u.rot1, t2 = u.trans * u.trans, t = std::abs(u.trans);
  const double turn = u.rot1 + u.rot2;  // the heading change the odometry reports
  MotionSpread s;
  // The direction of travel: Probabilistic Robotics eq. 5.37 (a1 rot1^2 + a2 trans^2) plus the
  // random walks; it moves the particle, its heading comes from the turn below.
  s.rot1 = std::sqrt(a.alpha1 * r1 + a.alpha2 * t2 + a.walk_turn * std::abs(u.rot1) + 0.5 * a.walk_heading * t);
  // eq. 5.38, with the turn for the rotations (see below).
  s.trans = std::sqrt(a.alpha3 * t2 + a.alpha4 * turn * turn + a.walk_trans * t);
  // The heading: the noise of the turn the robot made (eq. 5.37/5.39 with rot1 + rot2; the
  // translation's part a2 trans^2 in both, as in the book), not of the two rotations apart. The
  // direction of a short step is mostly noise itself (a scan matcher's jitter, a laser off the
  // turning axis swinging on an arc): split into "turn 89 deg, move 1 cm, turn back 88 deg", the
  // book's rotations would add 5.5 deg to the heading and alpha4 7 cm to the step for a turn of a
  // degree (Freiburg 079's rooms, rotating in place: the cloud's heading ran off by 40-90 deg).
  s.heading =
      std::sqrt(a.alpha1 * turn * turn + 2.0 * a.alpha2 * t2 + a.walk_turn * std::abs(turn) + a.walk_heading * t);
  return s;
}

Pose2 applyMotion(const Pose2& x, const OdometryDelta& u, const MotionSpread& s, double n_rot1, double n_trans,
                  double n_heading) {
  const double heading = x.theta + (u.rot1 - s.rot1 * n_rot1);
  const double trans = u.trans - s.trans * n_trans;
  return {x.t + trans * Vec2(std::cos(heading), std::sin(heading)),
          x.theta + (u.rot1 + u.rot2) - s.heading * n_heading};
}

Pose2 sampleMotionOdometry(const Pose2& x, const OdometryDelta& u, const OdometryNoise& a, std::mt19937_64& rng) {
  std::normal_distribution<double> n01(0.0, 1.0);
  const MotionSpread s = motionSpread(u, a);
  const double n_rot1 = n01(rng), n_trans = n01(rng);
  return applyMotion(x, u, s, n_rot1, n_trans, n01(rng));
}

}  // namespace glassmap::localize
