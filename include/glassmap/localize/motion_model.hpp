#pragma once
/// The odometry motion model (Probabilistic Robotics table 5.6, sample_motion_model_odometry).

#include <random>

#include "glassmap/core/pose2.hpp"

namespace glassmap::localize {

/// Noise of the odometry motion model: the four alphas of Probabilistic Robotics (variances that
/// grow with the square of each step: a scale error, the same share of every step) plus random
/// walks (variances that grow with the step: wheel slip and encoder noise, which add up over a
/// path whatever the rate the log was recorded at). The alphas alone make the noise per metre
/// depend on the step: at 1 cm steps a 22% alpha is 2 cm per metre, at 1 m steps 22 cm, so a log
/// subsampled to 1 m steps would drift along every corridor.
struct OdometryNoise {
  double alpha1 = 0.0025;        ///< rotation noise from rotation [rad^2 / rad^2] (5%)
  double alpha2 = 0.0012;        ///< rotation noise from translation [rad^2 / m^2] (2 deg per metre)
  double alpha3 = 0.0025;        ///< translation noise from translation [m^2 / m^2] (5%)
  double alpha4 = 0.001;         ///< translation noise from rotation [m^2 / rad^2]
  double walk_trans = 6.4e-4;    ///< translation random walk [m^2 per m] (2.5 cm after 1 m)
  double walk_heading = 1.3e-4;  ///< heading random walk from translation [rad^2 per m] (0.65 deg after 1 m)
  double walk_turn = 8.8e-4;     ///< heading random walk from turning [rad^2 per rad] (1.7 deg after 1 rad)
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

/// Samples x' ~ p(x' | u, x) with u = delta (Probabilistic Robotics eq. 5.37-5.45, the variances
/// extended by the random walks): the direction of travel rot1 with variance alpha1 rot1^2 +
/// alpha2 trans^2 + walk_turn |rot1| + walk_heading |trans| / 2, the translation with alpha3
/// trans^2 + alpha4 turn^2 + walk_trans |trans|, and the new heading from the turn = rot1 + rot2
/// with alpha1 turn^2 + 2 alpha2 trans^2 + walk_turn |turn| + walk_heading |trans|: the book's
/// noise on rot1 and rot2 apart would turn the heading (and stretch the step) of a robot rotating in
/// place by a twentieth of rot1 at every short step whose direction is jitter or an off-axis
/// laser's arc.
/// Backward motion (rot1 near +-pi) is folded into a negative translation so it does not count as
/// two half turns.
Pose2 sampleMotionOdometry(const Pose2& x, const OdometryDelta& delta, const OdometryNoise& noise,
                           std::mt19937_64& rng);

/// The standard deviations sampleMotionOdometry draws with: they depend on the increment and the
/// noise only, so a filter computes them once per step for all of its particles.
struct MotionSpread {
  double rot1 = 0.0;     ///< of the direction of travel [rad]
  double trans = 0.0;    ///< of the translation [m]
  double heading = 0.0;  ///< of the heading change [rad]
};
MotionSpread motionSpread(const OdometryDelta& delta, const OdometryNoise& noise);

/// The pose sampleMotionOdometry returns for the standard normal draws n_rot1, n_trans, n_heading
/// (in that order of drawing).
Pose2 applyMotion(const Pose2& x, const OdometryDelta& delta, const MotionSpread& spread, double n_rot1, double n_trans,
                  double n_heading);

}  // namespace glassmap::localize
