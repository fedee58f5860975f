#pragma once
// Binomial tails in log10: the a-contrario and least-rate tests of the sparse-pane search and the
// opaque-glass test.

#include <cmath>
#include <limits>

#include <boost/math/special_functions/beta.hpp>

namespace glassmap::glass::detail {

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
