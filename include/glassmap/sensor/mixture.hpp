#pragma once
/// The beam-model mixture (Probabilistic Robotics eq. 6.4-6.12) as densities over a reading z in
/// [0, z_max) plus a point mass at z_max. Shared by the beam and glass models.

#include <algorithm>
#include <cmath>
#include <span>

#include "glassmap/sensor/sensor_model.hpp"

namespace glassmap::sensor {

/// Normalised weights and shapes of the hit/short/max/random mixture.
struct Mixture {
  double w_hit = 0, w_short = 0, w_max = 0, w_rand = 0;  ///< weights summing to 1 [-]
  double sigma = 0.05;                                   ///< hit std dev [m]
  double sigma_rel = 0.0;                                ///< its growth with the reading (sigmaAt) [-]
  double lambda_short = 0.2;                             ///< short-reading rate [1/m]

  explicit Mixture(const SensorParams& p);

  /// The mixture of a reading z: sigma = hypot(sigma, sigma_rel z) (itself when sigma_rel is 0).
  /// The models take every density of a beam, whatever range a mode expects, with the sigma of
  /// its reading: for the pose that explains the reading the two are within a few sigma, and the
  /// sigma is the same for every particle (one kernel per beam).
  Mixture at(double z) const {
    Mixture m = *this;
    if (sigma_rel > 0 && std::isfinite(z)) m.sigma = std::hypot(sigma, sigma_rel * z);
    m.sigma_rel = 0.0;
    return m;
  }

  /// hitDensity is exactly 0 where ((z - e) / sigma)^2 exceeds this (below 1e-17 of the peak).
  static constexpr double kHitCutoff2 = 80.0;
  /// A distance in sigmas beyond that cutoff (sqrt 80 = 8.94) that rounding cannot cross: a mode
  /// expected more than kHitReach sigma beyond the reading adds exactly 0 to p(z < z_max).
  static constexpr double kHitReach = 10.0;

  /// Hit density at z [1/m] of a reading around expected range e, a Gaussian truncated and
  /// renormalised to [0, z_max); 0 when e >= z_max (then hitMass() is the point mass at z_max).
  double hitDensity(double z, double e, double z_max) const;
  /// Unnormalised Gaussian N(z; e, sigma) [1/m] (the paper's form).
  double gauss(double z, double e) const;
  /// Short-reading density at z [1/m] for a first surface at e (truncated exponential on [0, e)).
  double shortDensity(double z, double e, double z_max) const { return shortDensity(z, e, z_max, shortNumerator(z)); }
  /// Its numerator lambda exp(-lambda z), which depends on the reading only (a caller weighing many
  /// poses against one scan computes it once per beam), and the density from it.
  double shortNumerator(double z) const { return lambda_short * std::exp(-lambda_short * z); }
  double shortDensity(double z, double e, double z_max, double numerator) const;
  /// Uniform density 1 / z_max [1/m].
  static double randDensity(double z_max) { return 1.0 / z_max; }
  /// p(z) for one expected range e (+inf or >= z_max: no surface); z >= z_max is a max reading
  /// and returns its probability mass.
  double probability(double z, double e, double z_max) const {
    return probability(z, e, z_max, z < z_max ? shortNumerator(z) : 0.0);
  }
  /// The same with shortNumerator(z) given.
  double probability(double z, double e, double z_max, double short_numerator) const;
};

/// Sum of log p_i over beams for a per-beam probability function: multiplies blocks of 8 before
/// taking one log (each p_i lies in [z_rand / z_max, 1 / sigma], so a block cannot under- or
/// overflow) to save most of the logs.
template <class Prob>
double sumLogProbabilities(const Pose2& T_map_laser, const BeamSet& beams, Prob&& prob) {
  const Eigen::Matrix2d R = T_map_laser.rotation();
  double sum = 0.0, block = 1.0;
  for (std::size_t i = 0; i < beams.size(); ++i) {
    block *= prob(Vec2(R * beams.dirs[i]), beams.ranges[i]);
    if ((i & 7) == 7) {
      sum += std::log(block);
      block = 1.0;
    }
  }
  return sum + std::log(block);
}

/// sumLogProbabilities(poses[j], beams, prob(pose, dir, z)) into out[j] for every pose, beam-major
/// over blocks of 64 poses (the rays of one beam from nearby particles walk the same cells one
/// after the other, which keeps them in cache); each out[j] is computed operation for operation
/// as the one-pose call computes it.
template <class Prob>
void sumLogProbabilitiesBatch(std::span<const Pose2> poses, const BeamSet& beams, double* out, Prob&& prob) {
  constexpr std::size_t kBlock = 64;
  for (std::size_t j0 = 0; j0 < poses.size(); j0 += kBlock) {
    const std::size_t n = std::min(kBlock, poses.size() - j0);
    Eigen::Matrix2d R[kBlock];
    double sum[kBlock], block[kBlock];
    for (std::size_t j = 0; j < n; ++j) {
      R[j] = poses[j0 + j].rotation();
      sum[j] = 0.0;
      block[j] = 1.0;
    }
    for (std::size_t i = 0; i < beams.size(); ++i) {
      for (std::size_t j = 0; j < n; ++j) block[j] *= prob(poses[j0 + j], Vec2(R[j] * beams.dirs[i]), beams.ranges[i]);
      if ((i & 7) == 7) {
        for (std::size_t j = 0; j < n; ++j) {
          sum[j] += std::log(block[j]);
          block[j] = 1.0;
        }
      }
    }
    for (std::size_t j = 0; j < n; ++j) out[j0 + j] = sum[j] + std::log(block[j]);
  }
}

}  // namespace glassmap::sensor
