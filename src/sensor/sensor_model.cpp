#include "glassmap/sensor/sensor_model.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <vector>

#include "glassmap/core/error.hpp"
#include "glassmap/sensor/beam_model.hpp"
#include "glassmap/sensor/field_model.hpp"
#include "glassmap/sensor/glass_model.hpp"

namespace glassmap::sensor {

std::string_view toString(GlassAs g) { return g == GlassAs::Opaque ? "opaque" : "invisible"; }

GlassAs parseGlassAs(std::string_view s) {
  std::string lower(s);
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (lower == "opaque") return GlassAs::Opaque;
  if (lower == "invisible") return GlassAs::Invisible;
  throw Error("unknown glass treatment '" + std::string(s) + "' (expected opaque or invisible)", {}, 0, "glass-as");
}

BeamSet makeBeamSet(const LaserScan& scan, int count) {
  BeamSet set;
  set.max_range = scan.max_range;
  const std::size_t n = scan.ranges.size();
  if (n == 0) return set;
  const std::size_t k = (count <= 0 || static_cast<std::size_t>(count) >= n) ? n : static_cast<std::size_t>(count);
  set.angles.reserve(k);
  set.dirs.reserve(k);
  set.ranges.reserve(k);
  set.points.reserve(k);
  for (std::size_t j = 0; j < k; ++j) {
    // Evenly spread, first and last beam included.
    const std::size_t i = k == 1 ? n / 2 : (j * (n - 1) + (k - 1) / 2) / (k - 1);
    const double a = scan.beamAngle(i);
    const float r = scan.ranges[i];
    const double z = (std::isfinite(r) && r >= 0.0f) ? std::min<double>(r, scan.max_range) : scan.max_range;
    const Vec2 d(std::cos(a), std::sin(a));
    set.angles.push_back(a);
    set.dirs.push_back(d);
    set.ranges.push_back(z);
    set.points.push_back(z * d);
  }
  return set;
}

void SensorModel::logLikelihoods(std::span<const Pose2> poses, const BeamSet& beams, double* out) const {
  for (std::size_t j = 0; j < poses.size(); ++j) out[j] = logLikelihood(poses[j], beams);
}

double SensorModel::logLikelihood(const Pose2& T_map_laser, const BeamSet& beams) const {
  const Eigen::Matrix2d R = T_map_laser.rotation();
  double sum = 0.0;
  for (std::size_t i = 0; i < beams.size(); ++i)
    sum += logLikelihood(T_map_laser, R * beams.dirs[i], beams.ranges[i], beams.max_range);
  return sum;
}

double SensorModel::beamLogLikelihood(const Pose2& T_map_laser, double angle, double z, double max_range) const {
  const double a = T_map_laser.theta + angle;
  return logLikelihood(T_map_laser, Vec2(std::cos(a), std::sin(a)), z, max_range);
}

std::vector<std::string> sensorModelNames() { return {"glass", "glass-paper", "beam", "field"}; }

std::unique_ptr<SensorModel> makeSensorModel(std::string_view name, const VectorMap& map, const SensorParams& params) {
  if (name == "beam") return std::make_unique<BeamModel>(map, params);
  if (name == "field") return std::make_unique<FieldModel>(map, params);
  if (name == "glass") return std::make_unique<GlassModel>(map, params, GlassModel::Variant::Mixture);
  if (name == "glass-paper") return std::make_unique<GlassModel>(map, params, GlassModel::Variant::Paper);
  throw Error("unknown sensor model '" + std::string(name) + "' (expected glass, glass-paper, beam or field)", {}, 0,
              "model");
}

SensorParams paramsFromProfile(const SensorProfile& p, SensorParams base, double min_sigma_hit) {
  base.sigma_hit = std::max(p.range_sigma_m.value, min_sigma_hit);
  base.sigma_hit_rel = std::max(p.range_sigma_rel.value, 0.0);
  base.z_hit = p.w_hit.value;
  base.z_short = p.w_short.value;
  base.z_max = p.w_max.value;
  base.z_rand = std::max(p.w_rand.value, 1e-3);  // bounds the log-likelihood of a stray reading
  base.lambda_short = p.lambda_short.value;
  base.direct_sigma_deg = p.direct_sigma_deg.value;
  base.direct_peak = p.direct_peak.value;
  base.direct_floor = p.direct_floor.value;
  base.lambda_normal = p.normal_lambda_per_deg.value;
  base.normal_floor = p.normal_floor.value;
  return base;
}

}  // namespace glassmap::sensor
