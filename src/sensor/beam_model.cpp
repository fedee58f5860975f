#include "glassmap/sensor/beam_model.hpp"

#include <cmath>

namespace glassmap::sensor {
namespace {

VectorMap visibleMap(const VectorMap& map, GlassAs glass_as) {
  if (glass_as == GlassAs::Opaque) return map;
  VectorMap walls;
  walls.name = map.name;
  for (const MapSegment& s : map.segments)
    if (s.material == Material::Wall) walls.segments.push_back(s);
  return walls;
}

}  // namespace

BeamModel::BeamModel(const VectorMap& map, const SensorParams& params)
    : SensorModel(params), map_(map), caster_(visibleMap(map, params.glass_as)), mix_(params) {}

void BeamModel::setParams(const SensorParams& params) {
  mix_ = Mixture(params);
  const GlassAs glass_as = params_.glass_as;  // the caster was built for it
  params_ = params;
  params_.glass_as = glass_as;
}

double BeamModel::probability(const Vec2& origin, const Vec2& dir, double z, double max_range) const {
  const double e = caster_.castRange(origin, dir, max_range);  // +inf when nothing is hit
  return mix_.probability(z, e, max_range);
}

double BeamModel::logLikelihood(const Pose2& T_map_laser, const Vec2& dir, double z, double max_range) const {
  return std::log(probability(T_map_laser.t, dir, z, max_range));
}

double BeamModel::logLikelihood(const Pose2& T_map_laser, const BeamSet& beams) const {
  return sumLogProbabilities(T_map_laser, beams, [&](const Vec2& dir, double z) {
    return probability(T_map_laser.t, dir, z, beams.max_range);
  });
}

void BeamModel::logLikelihoods(std::span<const Pose2> poses, const BeamSet& beams, double* out) const {
  sumLogProbabilitiesBatch(poses, beams, out, [&](const Pose2& T_map_laser, const Vec2& dir, double z) {
    return probability(T_map_laser.t, dir, z, beams.max_range);
  });
}

}  // namespace glassmap::sensor
