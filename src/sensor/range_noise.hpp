#pragma once
// Private to sensor/: range noise as a function of range, sigma(r) = hypot(sigma0, rel * r), from
// residuals (self-calibration, calibrate.cpp).

#include <vector>

#include "glassmap/core/laser_scan.hpp"

namespace glassmap::sensor::detail {

/// The median of v (its upper middle for an even count; 0 when empty); v is reordered.
double median(std::vector<double>& v);

/// One noise sample: a residual in range units and the range it was read at.
struct RangeResidual {
  float range;  ///< [m]
  float z;      ///< [m]
};

/// The in-scan residual of each reading with returns on both sides: its distance from the line
/// through its two neighbours (a flat surface), measured along its beam. On a flat surface it is
/// r_i - (r_{i-1} + r_{i+1}) / 2 in noise (variance 1.5 sigma^2 for equal noise), whatever the
/// curvature of range against beam angle that a slanted wall and a coarse step give (the plain
/// second difference carries r step^2 (1 + 2 tan^2 theta) of it). Steep views (incidence over
/// 60 deg) and depth steps are left out.
void inScanResiduals(const LaserScan& scan, std::vector<RangeResidual>& out);

/// The noise sigma of residuals z (variance variance_factor * sigma^2 each) among readings that
/// straddle two surfaces: EM over a zero-mean Gaussian and a uniform outlier part spanning the
/// residuals, started from the median absolute deviation. Pure Gaussian residuals give their
/// maximum-likelihood scale; a fifth of broad outliers no longer inflates it.
double noiseScale(const std::vector<double>& z, double variance_factor);

/// A fit of sigma(r) = hypot(sigma0, rel * r) with standard errors; rel = 0 (not fitted) when the
/// data show no growth with range.
struct RangeNoiseFit {
  double sigma0 = 0.0, sigma0_se = 0.0;
  double rel = 0.0, rel_se = 0.0;
  bool rel_fitted = false;
  double median_range = 0.0;  ///< of the residuals used [m]
  bool ok = false;            ///< enough residuals
};

/// Robust fit: residuals in range bins (equal counts), each bin's sigma from its median absolute
/// deviation divided by sqrt(variance_factor) (1.5 for in-scan residuals, 1 for residuals against
/// a map), or by noiseScale when `broad_outliers` (in-scan residuals, which no map has gated), then
/// weighted least squares of sigma_b^2 = sigma0^2 + rel^2 r_b^2.
RangeNoiseFit fitRangeNoise(std::vector<RangeResidual> residuals, double variance_factor,
                            std::size_t min_residuals = 500, bool broad_outliers = false);

}  // namespace glassmap::sensor::detail
