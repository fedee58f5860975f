#include "glassmap/sensor/beam_model.hpp"
#include "mixture_pick.hpp"

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
  return mix_.at(z).probability(z, e, max_range);
}

double BeamModel::logLikelihood(const Pose2& T_map_laser, const Vec2& dir, double z, double max_range) const {
  return std::log(probability(T_map_laser.t, dir, z, max_range));
}

double BeamModel::logLikelihood(const Pose2& T_map_laser, const BeamSet& beams) const {
  double out = 0.0;  // the batch call for one pose: bit for bit what the filter's calls give it
  logLikelihoods(std::span<const Pose2>(&T_map_laser, 1), beams, &out);
  return out;
}

void BeamModel::logLikelihoods(std::span<const Pose2> poses, const BeamSet& beams, double* out) const {
  // The rays of up to 256 poses, beam-major: one beam of a particle cloud is a coherent group that
  // RayCaster::castGroups sweeps once (bit for bit castRange); the mixture on SIMD lanes where the
  // CPU has them (equal to Mixture::probability up to float rounding); then each pose's sum of logs
  // as sumLogProbabilities forms it.
  constexpr std::size_t kBlock = 256;
  thread_local std::vector<double> ox, oy, ux, uy, range, p, short_num;
  thread_local std::vector<std::uint8_t> fix;
  static const detail::MixtureLanesFn lanes_fn = detail::mixtureLanes();
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
    fix.resize(nr);
    p.resize(nr);
    for (std::size_t i = 0; i < nb; ++i) {
      const double z = beams.ranges[i];
      const Mixture mix = mix_.at(z);
      const bool lanes = lanes_fn && z < beams.max_range;  // SIMD lanes: equal up to float rounding
      if (lanes)
        lanes_fn(detail::lanesFor(mix, z, beams.max_range, short_num[i]), &range[i * n], &p[i * n], &fix[i * n], n);
      for (std::size_t k = i * n; k < (i + 1) * n; ++k)
        if (!lanes || fix[k]) p[k] = mix.probability(z, range[k], beams.max_range, short_num[i]);
    }
    for (std::size_t j = 0; j < n; ++j) {
      double sum = 0.0, block = 1.0;
      for (std::size_t i = 0; i < nb; ++i) {
        block *= p[i * n + j];
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
