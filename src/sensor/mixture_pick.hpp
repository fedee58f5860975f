#pragma once
/// Internal: the mixture-lanes kernel this CPU runs (null: none; the scalar Mixture then).

#include <cmath>

#include "glassmap/core/angles.hpp"
#include "glassmap/geometry/ray_caster.hpp"
#include "glassmap/sensor/mixture.hpp"
#include "mixture_lanes.hpp"

namespace glassmap::sensor::detail {

/// The kernel of the best instruction set this CPU has among AVX-512 and AVX2 (null: neither).
template <class Fn>
Fn forBestIsa(Fn avx512, Fn avx2) {
  switch (RayCaster::bestIsa()) {
    case RayIsa::Avx512: return avx512;
    case RayIsa::Avx2: return avx2;
    default: return nullptr;
  }
}

#if defined(GLASSMAP_MIXTURE_LANES)
inline MixtureLanesFn mixtureLanes() { return forBestIsa(mixtureLanesAvx512, mixtureLanesAvx2); }
/// The glass model's kernels this CPU runs (null: none; GlassModel's scalar pieces then).
inline GlassWeightsFn glassWeightsLanes() { return forBestIsa(glassWeightsAvx512, glassWeightsAvx2); }
inline GlassModesFn glassModesLanes() { return forBestIsa(glassModesAvx512, glassModesAvx2); }
#else
inline MixtureLanesFn mixtureLanes() { return nullptr; }
inline GlassWeightsFn glassWeightsLanes() { return nullptr; }
inline GlassModesFn glassModesLanes() { return nullptr; }
#endif

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
