#include "glassmap/sensor/mixture.hpp"

#include <cmath>

#include "glassmap/core/angles.hpp"
#include "glassmap/core/error.hpp"

namespace glassmap::sensor {
namespace {
double phi(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }
}  // namespace

Mixture::Mixture(const SensorParams& p) : sigma(p.sigma_hit), sigma_rel(p.sigma_hit_rel), lambda_short(p.lambda_short) {
  if (!(p.sigma_hit > 0)) throw Error("sigma_hit must be positive", {}, 0, "sigma_hit");
  if (!(p.sigma_hit_rel >= 0) || !std::isfinite(p.sigma_hit_rel))
    throw Error("sigma_hit_rel must be zero or positive", {}, 0, "sigma_hit_rel");
  if (p.z_hit < 0 || p.z_short < 0 || p.z_max < 0 || p.z_rand < 0)
    throw Error("mixture weights must not be negative", {}, 0, "z_hit");
  if (p.z_rand <= 0) throw Error("z_rand must be positive (it bounds the log-likelihood)", {}, 0, "z_rand");
  const double sum = p.z_hit + p.z_short + p.z_max + p.z_rand;
  w_hit = p.z_hit / sum;
  w_short = p.z_short / sum;
  w_max = p.z_max / sum;
  w_rand = p.z_rand / sum;
}

double Mixture::gauss(double z, double e) const {
  const double u = (z - e) / sigma;
  return std::exp(-0.5 * u * u) / (std::sqrt(2.0 * kPi) * sigma);
}

double Mixture::hitDensity(double z, double e, double z_max) const {
  if (!(e < z_max)) return 0.0;
  const double u = (z - e) / sigma;
  if (u * u > kHitCutoff2) return 0.0;  // below 1e-17 of the peak
  double eta = 1.0;                     // truncation to [0, z_max): only near either end it matters
  if (e < 6.0 * sigma || e > z_max - 6.0 * sigma) eta = 1.0 / (phi((z_max - e) / sigma) - phi(-e / sigma));
  return eta * gauss(z, e);
}

double Mixture::shortDensity(double z, double e, double z_max, double numerator) const {
  const double es = std::min(e, z_max);
  if (z >= es || es <= 1e-9 || lambda_short <= 0) return 0.0;
  return numerator / (-std::expm1(-lambda_short * es));
}

double Mixture::probability(double z, double e, double z_max, double short_numerator) const {
  if (z >= z_max) return w_max + (e < z_max ? 0.0 : w_hit);
  return w_hit * hitDensity(z, e, z_max) + w_short * shortDensity(z, e, z_max, short_numerator) + w_rand / z_max;
}

}  // namespace glassmap::sensor
