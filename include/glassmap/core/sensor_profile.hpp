#pragma once
/// A laser's sensor profile (DESIGN.md, "A sensor profile"): what a particular scanner does to a
/// beam, estimated from a log by sensor/calibrate.hpp, saved as YAML by io/sensor_profile.hpp and
/// used by every stage whose thresholds depend on the sensor (grid miss margins, the glass
/// classifiers' lobe, the vectorizer's noise floor, the localizer's beam and glass models).
/// Plain data: no module needs another to pass it around.

#include <cmath>
#include <cstddef>
#include <string>

namespace glassmap {

/// One fitted number with its standard error (0 = not estimated: a prior or a given value).
struct Estimate {
  double value = 0.0;
  double se = 0.0;      ///< standard error of value (same unit) [-]
  bool fitted = false;  ///< true: estimated from data; false: the default (prior) kept
};

/// The sensor's intrinsic parameters. Defaults are a generic scanner with a narrow glass lobe
/// (the paper's values): what every stage assumes when nothing is known about the sensor.
struct SensorProfile {
  // Beam model (Probabilistic Robotics 6.3) of beams whose first surface is a wall.
  Estimate range_sigma_m{0.02};  ///< sigma of a reading around the true range, its constant part [m]
  /// Range noise that grows with the range (triangulation and phase-shift scanners): the sigma at
  /// range r is hypot(range_sigma_m, range_sigma_rel * r) (rangeSigmaAt) [-].
  Estimate range_sigma_rel{0.0};
  Estimate w_hit{0.85};        ///< weight of hits [-]
  Estimate w_short{0.05};      ///< weight of unexpected short readings [-]
  Estimate w_max{0.05};        ///< weight of max-range readings on a real surface [-]
  Estimate w_rand{0.05};       ///< weight of uniformly random readings [-]
  Estimate lambda_short{0.2};  ///< rate of the short-reading exponential [1/m]
  // Glass (paper 2.1-2.3): P(direct | theta) = floor + (peak - floor) exp(-theta^2 / 2 sigma^2).
  Estimate direct_peak{0.9};             ///< P(direct return) at normal incidence [-]
  Estimate direct_sigma_deg{2.0};        ///< width of the direct-return lobe [deg]
  Estimate direct_floor{0.0};            ///< P(direct return) far off the lobe, at any angle [-]
  Estimate normal_lambda_per_deg{0.09};  ///< P(reflected | theta) = exp(-lambda (90 - theta)) [1/deg]
  Estimate normal_floor{0.0};            ///< ... plus this floor at any angle [-]
  Estimate glass_offset_m{0.0};          ///< extra range of a reading through one pane [m]
  // Where it came from.
  std::string source = "default";  ///< "default", "calibrated from <log>", a file name
  std::size_t wall_beams = 0;      ///< beams the beam-model fit used
  std::size_t glass_beams = 0;     ///< beams whose first surface was glass
  double max_range = 0.0;          ///< the scans' max range [m] (0 = unknown)
  /// Median range of the log's returns [m] (0 = unknown): of the wall returns the EM used, or, with
  /// the in-scan noise estimate (sensor::inScanNoise), of every return of the scans it used.
  double typical_range_m = 0.0;
};

/// Range noise sigma at range r [m]: hypot(range_sigma_m, range_sigma_rel * r).
inline double rangeSigmaAt(const SensorProfile& p, double range) {
  return std::hypot(p.range_sigma_m.value, p.range_sigma_rel.value * range);
}

/// The range noise that thresholds over a whole log use: the sigma at the typical range of its
/// returns (the constant part alone when that range is unknown) [m].
inline double typicalRangeSigma(const SensorProfile& p) { return rangeSigmaAt(p, p.typical_range_m); }

/// P(direct return | theta) of a profile, theta the incidence angle [deg].
inline double directProbability(const SensorProfile& p, double theta_deg) {
  const double s = p.direct_sigma_deg.value;
  return p.direct_floor.value +
         (p.direct_peak.value - p.direct_floor.value) * std::exp(-theta_deg * theta_deg / (2 * s * s));
}

/// P(return along the mirrored path | theta, no direct return) of a profile.
inline double reflectedProbability(const SensorProfile& p, double theta_deg) {
  return p.normal_floor.value +
         (1 - p.normal_floor.value) * std::exp(-p.normal_lambda_per_deg.value * (90.0 - theta_deg));
}

/// Measured glass-return fractions in one incidence-angle bin (what a calibration chart shows).
struct GlassAngleBin {
  double theta_lo = 0, theta_hi = 0;  ///< [deg]
  std::size_t beams = 0;              ///< glass beams whose direct return is distinguishable
  std::size_t direct = 0;             ///< ... that came back from the pane
  std::size_t mirror_beams = 0;       ///< beams not direct whose mirrored path is distinguishable
  std::size_t reflected = 0;          ///< ... that came back along the mirrored path
};

}  // namespace glassmap
