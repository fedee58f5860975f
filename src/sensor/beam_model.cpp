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
    : map_(map), caster_(visibleMap(map, params.glass_as)), mix_(params) {}

double BeamModel::logLikelihood(const Pose2& T_map_laser, const Vec2& dir, double z,
                                double max_range) const {
  const double e = caster_.castRange(T_map_laser.t, dir, max_range);  // +inf when nothing is hit
  return std::log(mix_.probability(z, e, max_range));
}

}  // namespace glassmap::sensor
