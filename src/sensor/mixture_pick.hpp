#pragma once
/// Internal: the mixture-lanes kernel this CPU runs (null: none; the scalar Mixture then).

#include <cmath>

#include "glassmap/core/angles.hpp"
#include "glassmap/geometry/ray_caster.hpp"
#include "glassmap/sensor/mixture.hpp"
#include "mixture_lanes.hpp"

namespace glassmap::sensor::detail {

inline MixtureLanesFn mixtureLanes() {
#if defined(GLASSMAP_MIXTURE_LANES)
  if (RayCaster::bestIsa() == RayIsa::Avx512) return mixtureLanesAvx512;
  if (RayCaster::bestIsa() == RayIsa::Avx2) return mixtureLanesAvx2;
#endif
  return nullptr;
}

/// The glass model's kernels this CPU runs (null: none; GlassModel's scalar pieces then).
inline GlassWeightsFn glassWeightsLanes() {
#if defined(GLASSMAP_MIXTURE_LANES)
  if (RayCaster::bestIsa() == RayIsa::Avx512) return glassWeightsAvx512;
  if (RayCaster::bestIsa() == RayIsa::Avx2) return glassWeightsAvx2;
#endif
  return nullptr;
}
inline GlassModesFn glassModesLanes() {
#if defined(GLASSMAP_MIXTURE_LANES)
  if (RayCaster::bestIsa() == RayIsa::Avx512) return glassModesAvx512;
  if (RayCaster::bestIsa() == RayIsa::Avx2) return glassModesAvx2;
#endif
  return nullptr;
}

/// The lanes' numbers for reading z < z_max of one beam.
inline MixtureLanes lanesFor(const Mixture& mix, double z, double z_max, double short_numerator) {
  MixtureLanes m;
  m.z = z;
  m.z_max = z_max;
  m.w_hit = mix.w_hit;
  m.w_short = mix.w_short;
  m.rand_density = mix.w_rand / z_max;
  m.sigma = mix.sigma;
  m.norm = 1.0 / (std::sqrt(2.0 * kPi) * mix.sigma);
  m.lambda = mix.lambda_short;
  m.short_numerator = short_numerator;
  m.cutoff2 = Mixture::kHitCutoff2;
  return m;
}

}  // namespace glassmap::sensor::detail
