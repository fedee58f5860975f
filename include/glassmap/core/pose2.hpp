#pragma once
/// Rigid 2D pose (SE(2)) on Eigen: translation [m] and heading [rad].

#include <Eigen/Core>

#include "glassmap/core/angles.hpp"

namespace glassmap {

using Vec2 = Eigen::Vector2d;

/// A pose T_a_b: maps points in frame b to frame a. theta is kept wrapped to (-pi, pi].
struct Pose2 {
  Vec2 t = Vec2::Zero();  ///< translation [m]
  double theta = 0.0;     ///< heading [rad]

  Pose2() = default;
  Pose2(double x, double y, double heading) : t(x, y), theta(wrapAngle(heading)) {}
  Pose2(const Vec2& translation, double heading) : t(translation), theta(wrapAngle(heading)) {}

  double x() const { return t.x(); }
  double y() const { return t.y(); }

  /// Rotation matrix of the heading.
  Eigen::Matrix2d rotation() const {
    const double c = std::cos(theta), s = std::sin(theta);
    Eigen::Matrix2d r;
    r << c, -s, s, c;
    return r;
  }

  /// Composition T_a_c = T_a_b * T_b_c.
  Pose2 operator*(const Pose2& b_c) const { return {t + rotation() * b_c.t, theta + b_c.theta}; }

  /// Transforms a point from frame b into frame a.
  Vec2 operator*(const Vec2& p_b) const { return t + rotation() * p_b; }

  /// Inverse T_b_a.
  Pose2 inverse() const { return {-(rotation().transpose() * t), -theta}; }

  /// Relative pose T_this_other = this^-1 * other (odometry increment from this to other).
  Pose2 between(const Pose2& other) const { return inverse() * other; }

  /// Interpolates on SE(2) by the shortest heading path: s = 0 gives a, s = 1 gives b.
  static Pose2 interpolate(const Pose2& a, const Pose2& b, double s) {
    return {a.t + s * (b.t - a.t), a.theta + s * angleDiff(b.theta, a.theta)};
  }
};

/// True when two poses agree within tolerances [m], [rad].
inline bool approxEqual(const Pose2& a, const Pose2& b, double tol_m = 1e-9, double tol_rad = 1e-9) {
  return (a.t - b.t).norm() <= tol_m && std::abs(angleDiff(a.theta, b.theta)) <= tol_rad;
}

}  // namespace glassmap
