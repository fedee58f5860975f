#include "glassmap/sensor/glass_model.hpp"

#include <cmath>
#include <limits>

#include "glassmap/geometry/optics.hpp"

namespace glassmap::sensor {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Modes with a weight below this skip their ray cast (exp(-0.09 (90 - theta)) is never exactly 0).
constexpr double kNegligible = 1e-4;

}  // namespace

GlassModel::GlassModel(const VectorMap& map, const SensorParams& params, Variant variant)
    : SensorModel(params), caster_(map), mix_(params), variant_(variant) {
  panes_.reserve(map.segments.size());
  for (const MapSegment& s : map.segments) {
    panes_.push_back({s.b - s.a, s.direction(), (s.b - s.a).norm(), s.thickness});
    materials_.push_back(s.material);
  }
}

void GlassModel::setParams(const SensorParams& params) {
  mix_ = Mixture(params);  // validates before anything changes
  params_ = params;
}

GlassModes GlassModel::weights(const RayHit& hit) const {
  GlassModes m;
  m.d_g = hit.range;
  m.theta_deg = rad2deg(hit.incidence);
  // Paper eq. (2.1): direct-reflection lobe; (2.2): normal reflection; (2.3): refraction.
  // With a measured profile: a peak below 1 and floors at any angle (defaults 1, 0, 0: the paper).
  // (exp below -746 is exactly 0: taking that branch skips libm's slow underflow path, same bits.)
  const double lobe = -m.theta_deg * m.theta_deg / (2.0 * params_.direct_sigma_deg * params_.direct_sigma_deg);
  m.w_direct =
      params_.direct_floor + (params_.direct_peak - params_.direct_floor) * (lobe < -746.0 ? 0.0 : std::exp(lobe));
  m.w_normal =
      params_.normal_floor + (1.0 - params_.normal_floor) * std::exp(-params_.lambda_normal * (90.0 - m.theta_deg));
  m.w_refract = std::max(0.0, 1.0 - m.w_normal - m.w_direct);
  m.e_normal = kInf;
  m.e_refract = kInf;
  return m;
}

Vec2 GlassModel::mirrored(std::int32_t pane, const Vec2& dir) const {
  const Vec2& t = panes_[static_cast<std::size_t>(pane)].t;
  return 2.0 * dir.dot(t) * t - dir;
}

double GlassModel::elongation(std::int32_t pane, const Vec2& dir) const {
  // paneRangeElongation (geometry/optics.hpp), t (n / cos theta_t - 1 / cos theta_i), from the
  // cosines themselves: cos theta_i = |dir x d| / |d|, sin theta_i = |dir . d| / |d| for the
  // pane's vector d, and Snell's sin theta_t = sin theta_i / n; no sin, asin or cos.
  if (params_.offset >= 0) return params_.offset;
  const Pane& s = panes_[static_cast<std::size_t>(pane)];
  if (s.thickness == 0.0) return 0.0;
  const Vec2& d = s.d;
  const double len = s.len;
  const double cos_i = std::min(1.0, std::abs(dir.x() * d.y() - dir.y() * d.x()) / len);
  const double sin_t = std::min(1.0, std::abs(dir.dot(d)) / len) * (kAirIndex / params_.glass_index);
  const double cos_t = std::sqrt(std::max(0.0, 1.0 - sin_t * sin_t));
  return params_.glass_index * (s.thickness / cos_t) - s.thickness / cos_i;
}

GlassModel::Transmitted GlassModel::transmitted(const GlassModes&, const RayHit& hit, const Vec2& p,
                                                const Vec2& dir) const {
  // d_real: the straight ray continued through this pane (and up to max_panes - 1 more) to a
  // wall; offset: each pane's elongation, or the fixed per-pane offset when one is set.
  return {p, hit.range, elongation(hit.segment, dir), hit.segment, 1};
}

bool GlassModel::goesOn(Transmitted& t, const RayHit& next, const Vec2& dir, double& e_refract) const {
  if (!next.hit()) return false;
  t.travelled += next.range;
  if (next.material == Material::Wall || t.k == params_.max_panes) {
    e_refract = t.travelled + t.offset;
    return false;
  }
  t.offset += elongation(next.segment, dir);
  t.o = t.o + next.range * dir;
  t.skip = next.segment;
  ++t.k;
  return true;
}

GlassModes GlassModel::modes(const Vec2& origin, const Vec2& dir, const RayHit& hit, double max_range) const {
  GlassModes m = weights(hit);
  const Vec2 p = origin + hit.range * dir;
  if (m.w_normal > kNegligible) {
    // d_o: along the ray mirrored at the pane, to the next surface of any material.
    const double d_o = caster_.castRange(p, mirrored(hit.segment, dir), max_range - m.d_g, hit.segment);
    m.e_normal = m.d_g + d_o;
  }
  if (m.w_refract > kNegligible && params_.max_panes >= 1) {
    Transmitted t = transmitted(m, hit, p, dir);
    while (goesOn(t, caster_.castSurface(t.o, dir, max_range - t.travelled, t.skip), dir, m.e_refract)) {
    }
  }
  return m;
}

double GlassModel::logLikelihood(const Pose2& T_map_laser, const Vec2& dir, double z, double max_range) const {
  return std::log(probability(T_map_laser.t, dir, z, max_range));
}

double GlassModel::logLikelihood(const Pose2& T_map_laser, const BeamSet& beams) const {
  double out = 0.0;  // the batch call for one pose (glass_batch.cpp): bit for bit the filter's calls
  logLikelihoods(std::span<const Pose2>(&T_map_laser, 1), beams, &out);
  return out;
}

double GlassModel::probability(const Vec2& origin, const Vec2& dir, double z, double max_range) const {
  // The incidence angle (an atan) only where the model uses it: on glass.
  RayHit hit = caster_.castSurface(origin, dir, max_range);
  const Mixture mix = mix_.at(z);
  if (!hit.hit() || hit.material == Material::Wall) return mix.probability(z, hit.range, max_range);
  hit.incidence = caster_.incidence(hit.segment, dir);
  return fromModes(mix, modes(origin, dir, hit, max_range), z, max_range, z < max_range ? mix.shortNumerator(z) : 0.0);
}

double GlassModel::fromModes(const Mixture& mix, const GlassModes& m, double z, double max_range,
                             double short_numerator) const {
  const bool max_reading = z >= max_range;
  if (variant_ == Variant::Mixture) {
    const double sum = m.w_direct + m.w_normal + m.w_refract;  // > 0: w_normal never vanishes
    const double wd = m.w_direct / sum, wn = m.w_normal / sum, wr = m.w_refract / sum;
    double p;
    if (max_reading) {
      // Modes whose surface lies beyond z_max put their weight on the max reading.
      const double beyond = (m.e_normal < max_range ? 0.0 : wn) + (m.e_refract < max_range ? 0.0 : wr);
      p = mix.w_max + mix.w_hit * beyond;
    } else {
      const double hit_density = wd * mix.hitDensity(z, m.d_g, max_range) +
                                 wn * mix.hitDensity(z, m.e_normal, max_range) +
                                 wr * mix.hitDensity(z, m.e_refract, max_range);
      p = mix.w_hit * hit_density + mix.w_short * mix.shortDensity(z, m.d_g, max_range, short_numerator) +
          mix.w_rand / max_range;
    }
    return p;
  }
  // Paper 2.4, as written: alpha_1 = (z, ref), alpha_2 = (z, norm), alpha_3 = (z, direct), each the
  // mode's weight times an unnormalised Gaussian; a mode meeting nothing expects z_max.
  const double zz = std::min(z, max_range);
  const double a1 = m.w_refract * mix.gauss(zz, std::min(m.e_refract, max_range));
  const double a2 = m.w_normal * mix.gauss(zz, std::min(m.e_normal, max_range));
  const double a3 = m.w_direct * mix.gauss(zz, m.d_g);
  const double p = a1 + a2 + a3 - a1 * a2 - a1 * a3 - a2 * a3;
  // Guard: the formula goes negative when two densities exceed 1; floor at the random density.
  return std::max(p, mix.w_rand / max_range);
}

}  // namespace glassmap::sensor
