#pragma once
// Binomial tails in log10: the a-contrario and least-rate tests of the sparse-pane search and the
// opaque-glass test.

#include <cmath>
#include <limits>

#include <boost/math/special_functions/beta.hpp>
#include <boost/math/special_functions/gamma.hpp>

namespace glassmap::glass::detail {

/// log10 of P(X = k) for X ~ Binomial(n, p), 0 <= k <= n: where a tail falls below the smallest
/// double, its largest term (a lower bound, within a small factor that deep), so that a report
/// reads a number and not -infinity.
inline double log10BinomialTerm(int k, int n, double p) {
  if (p <= 0.0) return k == 0 ? 0.0 : -std::numeric_limits<double>::infinity();
  if (p >= 1.0) return k == n ? 0.0 : -std::numeric_limits<double>::infinity();
  using boost::math::lgamma;
  const double ln =
      lgamma(n + 1.0) - lgamma(k + 1.0) - lgamma(n - k + 1.0) + k * std::log(p) + (n - k) * std::log1p(-p);
  return ln / std::log(10.0);
}

/// log10 of P(X >= k) for X ~ Binomial(n, p).
inline double log10BinomialTail(int k, int n, double p) {
  if (k <= 0) return 0.0;
  if (k > n) n = k;
  if (p >= 1.0) return 0.0;
  const double tail = boost::math::ibeta(static_cast<double>(k), static_cast<double>(n - k + 1), p);
  return tail > 0.0 ? std::log10(tail) : log10BinomialTerm(k, n, p);
}

/// log10 of P(X <= k) for X ~ Binomial(n, p), 0 < p < 1: the regularised incomplete beta's complement.
inline double log10BinomialCdf(int k, int n, double p) {
  if (k >= n) return 0.0;
  const double cdf = boost::math::ibetac(static_cast<double>(k + 1), static_cast<double>(n - k), p);
  return cdf > 0.0 ? std::log10(cdf) : log10BinomialTerm(k, n, p);
}

}  // namespace glassmap::glass::detail
