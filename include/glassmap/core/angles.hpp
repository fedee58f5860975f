#pragma once
/// Angle helpers: wrapping and unit conversion. Angles are radians unless a name says otherwise.

#include <cmath>
#include <numbers>

namespace glassmap {

inline constexpr double kPi = std::numbers::pi;

/// Degrees to radians.
constexpr double deg2rad(double deg) { return deg * (kPi / 180.0); }
/// Radians to degrees.
constexpr double rad2deg(double rad) { return rad * (180.0 / kPi); }

/// Wraps an angle to (-pi, pi] [rad].
inline double wrapAngle(double a) {
  if (a > -kPi && a <= kPi) return a;
  a = std::remainder(a, 2.0 * kPi);  // in [-pi, pi]
  return a <= -kPi ? a + 2.0 * kPi : a;
}

/// Wraps an angle to [0, pi) [rad]: the direction of an undirected line.
inline double wrapHalfTurn(double a) {
  a = std::fmod(a, kPi);
  if (a < 0.0) a += kPi;
  return a >= kPi ? 0.0 : a;
}

/// Signed smallest difference a - b, in (-pi, pi] [rad].
inline double angleDiff(double a, double b) { return wrapAngle(a - b); }

}  // namespace glassmap
