#include "range_noise.hpp"

#include <algorithm>
#include <cmath>

#include "glassmap/core/angles.hpp"

namespace glassmap::sensor::detail {

void inScanResiduals(const LaserScan& scan, std::vector<RangeResidual>& out) {
  const double step = std::abs(scan.angular_step);
  for (std::size_t i = 1; i + 1 < scan.ranges.size(); ++i) {
    if (!scan.isReturn(i - 1) || !scan.isReturn(i) || !scan.isReturn(i + 1)) continue;
    const double a = scan.ranges[i - 1], b = scan.ranges[i], c = scan.ranges[i + 1];
    if (a < 0.05 || b < 0.05 || c < 0.05) continue;
    // Near-flat triples only: neighbours far apart in range are a step or a grazing view.
    if (std::abs(c - a) > 6.0 * b * step) continue;
    const double fa = scan.beamAngle(i - 1), fb = scan.beamAngle(i), fc = scan.beamAngle(i + 1);
    const Vec2 pa = a * Vec2(std::cos(fa), std::sin(fa)), pb = b * Vec2(std::cos(fb), std::sin(fb)),
               pc = c * Vec2(std::cos(fc), std::sin(fc));
    const Vec2 chord = pc - pa;
    const double len = chord.norm();
    if (!(len > 0)) continue;
    const Vec2 n(-chord.y() / len, chord.x() / len);
    const double along = n.dot(Vec2(std::cos(fb), std::sin(fb)));  // cos of the incidence
    if (std::abs(along) < 0.5) continue;
    out.push_back({static_cast<float>(b), static_cast<float>(n.dot(pb - pa) / along)});
  }
}

double median(std::vector<double>& v) {
  if (v.empty()) return 0.0;
  auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

double noiseScale(const std::vector<double>& z, double variance_factor) {
  if (z.empty()) return 0.0;
  // Start: the median absolute deviation, the scale of the Gaussian part if outliers were few.
  std::vector<double> dev(z.size());
  double span = 0.0;
  for (std::size_t i = 0; i < z.size(); ++i) {
    dev[i] = std::abs(z[i]);
    span = std::max(span, dev[i]);
  }
  double s = 1.4826 * median(dev);
  if (!(s > 0.0) || !(span > 0.0)) return s / std::sqrt(variance_factor);
  // EM over a zero-mean Gaussian and a uniform over [-span, span]: readings that straddle two
  // surfaces (a pane and the wall seen through it, an edge) are spread far wider than the noise;
  // counted in a median they inflate it (a fifth of such residuals: by about 30%).
  const double uniform = 1.0 / (2.0 * span);
  double outliers = 0.1;
  for (int iteration = 0; iteration < 50; ++iteration) {
    const double norm = (1.0 - outliers) / (std::sqrt(2.0 * kPi) * s);
    double w_sum = 0.0, wz2 = 0.0;
    for (const double d : dev) {
      const double g = norm * std::exp(-0.5 * (d / s) * (d / s));
      const double w = g / (g + outliers * uniform);
      w_sum += w;
      wz2 += w * d * d;
    }
    if (!(w_sum > 0.0)) break;
    const double next = std::sqrt(wz2 / w_sum);
    outliers = std::clamp(1.0 - w_sum / static_cast<double>(dev.size()), 1e-6, 0.9);
    const bool settled = std::abs(next - s) < 1e-6 * s;
    s = next;
    if (settled) break;
  }
  return s / std::sqrt(variance_factor);
}

RangeNoiseFit fitRangeNoise(std::vector<RangeResidual> r, double variance_factor, std::size_t min_residuals,
                            bool broad_outliers) {
  RangeNoiseFit fit;
  if (r.size() < min_residuals) return fit;
  fit.ok = true;
  std::sort(r.begin(), r.end(), [](const RangeResidual& x, const RangeResidual& y) { return x.range < y.range; });
  fit.median_range = r[r.size() / 2].range;
  // Residuals already gated against a map: their median absolute deviation (unbiased well inside
  // the gate, where the EM's uniform part would take the gate's tails for outliers).
  auto scaleOf = [&](std::vector<double>& z) {
    if (broad_outliers) return noiseScale(z, variance_factor);
    for (double& v : z) v = std::abs(v);
    return 1.4826 * median(z) / std::sqrt(variance_factor);
  };
  // The pooled estimate: the one to keep when sigma does not grow with range.
  std::vector<double> all(r.size());
  for (std::size_t i = 0; i < r.size(); ++i) all[i] = r[i].z;
  const double pooled = scaleOf(all);
  fit.sigma0 = pooled;
  fit.sigma0_se = 1.2533 * pooled / std::sqrt(static_cast<double>(r.size()));
  // Range bins of equal counts (at least 200 residuals each, at most 12 bins).
  const std::size_t bins = std::clamp<std::size_t>(r.size() / 200, 1, 12);
  if (bins < 4) return fit;
  std::vector<double> x, y, w;  // r_b^2, sigma_b^2, weight
  for (std::size_t b = 0; b < bins; ++b) {
    const std::size_t lo = b * r.size() / bins, hi = (b + 1) * r.size() / bins;
    std::vector<double> d;
    double sum_r = 0;
    for (std::size_t i = lo; i < hi; ++i) {
      d.push_back(r[i].z);
      sum_r += r[i].range;
    }
    const double s = scaleOf(d), n = static_cast<double>(hi - lo);
    const double rb = sum_r / n;
    x.push_back(rb * rb);
    y.push_back(s * s);
    w.push_back(n / std::max(s * s * s * s, 1e-16));  // var(s^2) ~ 5.4 s^4 / n for a MAD estimate
  }
  // Weighted least squares y = a + b x.
  double sw = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    sw += w[k];
    sx += w[k] * x[k];
    sy += w[k] * y[k];
    sxx += w[k] * x[k] * x[k];
    sxy += w[k] * x[k] * y[k];
  }
  const double det = sw * sxx - sx * sx;
  if (!(det > 0)) return fit;
  const double b = (sw * sxy - sx * sy) / det, a = (sy - b * sx) / sw;
  // Residual scatter of the bins about the line gives the slope's standard error.
  double chi = 0;
  for (std::size_t k = 0; k < x.size(); ++k) chi += w[k] * (y[k] - a - b * x[k]) * (y[k] - a - b * x[k]);
  const double dof = static_cast<double>(x.size()) - 2.0;
  const double b_se = std::sqrt(std::max(chi / dof, 5.4) * sw / det);
  if (!(b > 3.0 * b_se)) return fit;  // no growth with range the data can tell
  fit.rel_fitted = true;
  fit.rel = std::sqrt(b);
  fit.rel_se = 0.5 * b_se / fit.rel;
  const double a_se = std::sqrt(std::max(chi / dof, 5.4) * sxx / det);
  fit.sigma0 = std::sqrt(std::max(a, 1e-8));
  fit.sigma0_se = 0.5 * a_se / std::max(fit.sigma0, 1e-4);
  return fit;
}

}  // namespace glassmap::sensor::detail
