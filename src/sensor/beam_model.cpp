#include "glassmap/sensor/beam_model.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

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
  // The rays of up to 256 poses, beam-major: one beam of a particle cloud is a coherent group that
  // RayCaster::castGroups sweeps once (bit for bit castRange); then each pose's sum of logs exactly
  // as sumLogProbabilities forms it.
  constexpr std::size_t kBlock = 256;
  thread_local std::vector<double> ox, oy, ux, uy, range, short_num;
  thread_local std::vector<std::size_t> ends;
  const std::size_t nb = beams.size();
  short_num.resize(nb);
  for (std::size_t i = 0; i < nb; ++i)
    short_num[i] = beams.ranges[i] < beams.max_range ? mix_.shortNumerator(beams.ranges[i]) : 0.0;
  for (std::size_t j0 = 0; j0 < poses.size(); j0 += kBlock) {
    const std::size_t n = std::min(kBlock, poses.size() - j0), nr = n * nb;
    for (auto* v : {&ox, &oy, &ux, &uy, &range}) v->resize(nr);
    ends.resize(nb);
    for (std::size_t j = 0; j < n; ++j) {
      const Pose2& T = poses[j0 + j];
      const Eigen::Matrix2d R = T.rotation();
      for (std::size_t i = 0; i < nb; ++i) {
        const Vec2 dir(R * beams.dirs[i]);  // as sumLogProbabilities computes it
        ox[i * n + j] = T.t.x();
        oy[i * n + j] = T.t.y();
        ux[i * n + j] = dir.x();
        uy[i * n + j] = dir.y();
      }
    }
    for (std::size_t i = 0; i < nb; ++i) ends[i] = (i + 1) * n;
    RayBatch rays;
    rays.ox = ox.data();
    rays.oy = oy.data();
    rays.ux = ux.data();
    rays.uy = uy.data();
    rays.range = beams.max_range;
    rays.size = nr;
    caster_.castGroups(rays, ends.data(), nb, range.data());
    for (std::size_t i = 0; i < nb; ++i)
      for (std::size_t k = i * n; k < (i + 1) * n; ++k)
        range[k] = mix_.probability(beams.ranges[i], range[k], beams.max_range, short_num[i]);
    for (std::size_t j = 0; j < n; ++j) {
      double sum = 0.0, block = 1.0;
      for (std::size_t i = 0; i < nb; ++i) {
        block *= range[i * n + j];
        if ((i & 7) == 7) {
          sum += std::log(block);
          block = 1.0;
        }
      }
      out[j0 + j] = sum + std::log(block);
    }
  }
}

}  // namespace glassmap::sensor
