#pragma once
/// The odometry motion model (Probabilistic Robotics table 5.6, sample_motion_model_odometry).

#include <random>

#include "glassmap/core/pose2.hpp"

namespace glassmap::localize {

/// Noise of the odometry motion model: the four alphas of Probabilistic Robotics.
struct OdometryNoise {
  double alpha1 = 0.05;  ///< rotation noise from rotation [rad^2 / rad^2]
  double alpha2 = 0.01;  ///< rotation noise from translation [rad^2 / m^2]
  double alpha3 = 0.05;  ///< translation noise from translation [m^2 / m^2]
  double alpha4 = 0.01;  ///< translation noise from rotation [m^2 / rad^2]
};

/// An odometry increment split into rotate, translate, rotate.
struct OdometryDelta {
  double rot1 = 0.0;   ///< first rotation [rad]
  double trans = 0.0;  ///< translation [m]
  double rot2 = 0.0;   ///< second rotation [rad]
};

/// The increment from odometry pose `from` to `to` (both in the odometry frame). A translation
/// under 1 mm gets rot1 = 0 (the direction of a tiny step is noise).
OdometryDelta odometryDelta(const Pose2& from, const Pose2& to);

/// Samples x' ~ p(x' | u, x) with u = delta (Probabilistic Robotics eq. 5.37-5.45). Backward motion
/// (rot1 near +-pi) is folded into a negative translation so it does not count as two half turns.
Pose2 sampleMotionOdometry(const Pose2& x, const OdometryDelta& delta, const OdometryNoise& noise,
                           std::mt19937_64& rng);

}  // namespace glassmap::localize
