// Scans of a few straight walls for the vector tests that fit to returns (scan_fit, scan_clutter).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "glassmap/core/angles.hpp"
#include "glassmap/core/laser_scan.hpp"
#include "glassmap/geometry/vector_map.hpp"

namespace glassmap::vector::synthetic {

// A 360-beam scan from `at` of the walls `truth` (the nearest crossing per beam; none within 30 m:
// no return), with Gaussian range noise of sigma `noise` [m].
inline LaserScan scanOf(const Pose2& at, const std::vector<MapSegment>& truth, std::mt19937_64& rng,
                        double noise = 0.01) {
  LaserScan s;
  s.start_angle = -kPi;
  s.angular_step = 2.0 * kPi / 360.0;
  s.max_range = 30.0;
  s.laser_pose = at;
  std::normal_distribution<double> n(0.0, noise);
  for (int i = 0; i < 360; ++i) {
    const double th = at.theta + s.beamAngle(static_cast<std::size_t>(i));
    const Vec2 d(std::cos(th), std::sin(th));
    double best = 40.0;
    for (const MapSegment& w : truth) {
      const Vec2 e = w.b - w.a, q = w.a - at.t;
      const double den = d.x() * e.y() - d.y() * e.x();
      if (std::abs(den) < 1e-12) continue;
      const double t = (q.x() * e.y() - q.y() * e.x()) / den, u = (q.x() * d.y() - q.y() * d.x()) / den;
      if (t > 0 && u >= 0 && u <= 1) best = std::min(best, t);
    }
    s.ranges.push_back(best < 30.0 ? static_cast<float>(best + n(rng)) : std::numeric_limits<float>::infinity());
  }
  return s;
}

}  // namespace glassmap::vector::synthetic
