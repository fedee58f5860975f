// Binomial tails in log10 (src/glass/binomial.hpp), where they fall below the smallest double.

#include <gtest/gtest.h>

#include <cmath>

#include "binomial.hpp"

namespace glassmap::glass::detail {
namespace {

// 3,000 of 3,000 near-normal beams back at a background of 1%: P = 1e-6000, far below the smallest
// double (1e-308). The tail used to read -infinity there, and stats.json a null for the pane's
// log10 NFA; its largest term is a number, and this deep the tail's value within a small factor.
TEST(Binomial, TailsBelowTheSmallestDoubleReadAsNumbers) {
  EXPECT_NEAR(log10BinomialTail(3000, 3000, 0.01), -6000.0, 1e-6);
  EXPECT_NEAR(log10BinomialCdf(0, 3000, 0.99), -6000.0, 1e-6);
  const double deep = log10BinomialTail(2000, 3000, 0.01);
  EXPECT_TRUE(std::isfinite(deep));
  EXPECT_LT(deep, -308.0);
  EXPECT_GT(deep, log10BinomialTail(2001, 3000, 0.01));  // still falls as k grows
}

// Where the tail is a double, it is the sum of its terms and at least the largest: here within a
// factor of 1.12 of it (50 of 100 at 0.1).
TEST(Binomial, TheLargestTermBoundsADeepTailFromBelow) {
  const double tail = log10BinomialTail(50, 100, 0.1), term = log10BinomialTerm(50, 100, 0.1);
  EXPECT_GE(tail, term);
  EXPECT_LT(tail - term, std::log10(1.2));
  EXPECT_DOUBLE_EQ(log10BinomialTerm(0, 10, 0.0), 0.0);
  EXPECT_TRUE(std::isinf(log10BinomialTerm(3, 10, 0.0)));
}

}  // namespace
}  // namespace glassmap::glass::detail
