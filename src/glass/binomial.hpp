#pragma once
// Binomial tails in log10 (the a-contrario and least-rate tests of the sparse-pane search and the
// opaque-glass test), and the least return rate near its normal that a pane shows.

#include <cmath>
#include <limits>

#include <boost/math/special_functions/beta.hpp>

namespace glassmap::glass::detail {

/// The least share of the beams along its normal that a pane returns: rplidar-a2's faint lobe
/// (peak 0.3, sigma 1 deg) averaged over a 5 deg bin and spread over the cells a pane crosses
/// returns about 0.08-0.15 per cell; a run's near-normal beams (within 3 deg) on the 39 random
/// lasers' sparse panes 0.073 at least (tools/sensor_sweep.py, no people). The calibration takes a
/// lobe down to a peak of 0.05 (pipeline::MapOptions::min_lobe_peak).
inline constexpr double kLeastNormalRate = 0.05;

/// log10 of P(X >= k) for X ~ Binomial(n, p).
inline double log10BinomialTail(int k, int n, double p) {
  if (k <= 0) return 0.0;
  if (k > n) n = k;
  if (p >= 1.0) return 0.0;
  const double tail = boost::math::ibeta(static_cast<double>(k), static_cast<double>(n - k + 1), p);
  return tail > 0.0 ? std::log10(tail) : -std::numeric_limits<double>::infinity();
}

/// log10 of P(X <= k) for X ~ Binomial(n, p), 0 < p < 1: the regularised incomplete beta's complement.
inline double log10BinomialCdf(int k, int n, double p) {
  if (k >= n) return 0.0;
  const double cdf = boost::math::ibetac(static_cast<double>(k + 1), static_cast<double>(n - k), p);
  return cdf > 0.0 ? std::log10(cdf) : -std::numeric_limits<double>::infinity();
}

}  // namespace glassmap::glass::detail
