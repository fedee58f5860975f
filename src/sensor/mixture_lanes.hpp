#pragma once
/// Internal: the beam-model mixture (Mixture::probability) for many expected ranges of one reading
/// at once, with the SIMD exp/expm1 of glibc's libmvec (mixture_lanes_avx2.cpp, _avx512.cpp;
/// picked at run time like the ray caster's kernels). The results equal Mixture::probability up to
/// float rounding (libmvec's exp and expm1 are within 4 ulp of the scalar ones); a test holds the
/// models' batch calls to the per-beam reference.

#include <cstddef>
#include <cstdint>

namespace glassmap::sensor::detail {

/// The mixture's numbers for one beam's reading z < z_max.
struct MixtureLanes {
  double z = 0, z_max = 0;        ///< the reading and the scan's max range [m]
  double w_hit = 0, w_short = 0;  ///< normalised weights [-]
  double rand_density = 0;        ///< w_rand / z_max [1/m]
  double sigma = 0, norm = 0;     ///< hit sigma [m] and 1 / (sqrt(2 pi) sigma) [1/m]
  double lambda = 0;              ///< short-reading rate [1/m]
  double short_numerator = 0;     ///< lambda exp(-lambda z) [1/m]
  double cutoff2 = 80;            ///< Mixture::kHitCutoff2 [-]
};

/// p[k] for expected range e[k], k in [0, n). Where the hit density's truncation factor is not 1
/// (e within 6 sigma of 0 or of z_max) fix[k] = 1 and p[k] is left for the caller to compute with
/// Mixture::probability; else fix[k] = 0.
using MixtureLanesFn = void (*)(const MixtureLanes& m, const double* e, double* p, std::uint8_t* fix, std::size_t n);
void mixtureLanesAvx2(const MixtureLanes& m, const double* e, double* p, std::uint8_t* fix, std::size_t n);
void mixtureLanesAvx512(const MixtureLanes& m, const double* e, double* p, std::uint8_t* fix, std::size_t n);

/// The glass model's numbers on lanes (GlassModel::weights and fromModes, the same formulas with
/// libmvec's atan and exp, within 4 ulp of the scalar ones). Arrays hold n entries rounded up to a
/// multiple of kGlassPad; the caller fills the padding with any finite numbers (its results are
/// written and ignored).
constexpr std::size_t kGlassPad = 8;

/// The weights' parameters (SensorParams' glass lobe and reflection rate).
struct GlassWeightLanes {
  double two_sigma2 = 1;                     ///< 2 direct_sigma_deg^2 [deg^2]
  double direct_floor = 0, direct_span = 1;  ///< floor and peak - floor of P(direct) [-]
  double normal_floor = 0, lambda = 0.09;    ///< floor of P(norm) [-] and its rate [1/deg]
};
/// Rays that met a pane: unit direction (ux, uy), the pane's vector b - a (dx, dy); out: the
/// incidence [deg] and the three weights of GlassModel::weights.
struct GlassWeightRays {
  const double *ux = nullptr, *uy = nullptr, *dx = nullptr, *dy = nullptr;
  double *theta = nullptr, *wd = nullptr, *wn = nullptr, *wr = nullptr;
};
using GlassWeightsFn = void (*)(const GlassWeightLanes& m, const GlassWeightRays& r, std::size_t n);
void glassWeightsAvx2(const GlassWeightLanes& m, const GlassWeightRays& r, std::size_t n);
void glassWeightsAvx512(const GlassWeightLanes& m, const GlassWeightRays& r, std::size_t n);

/// One beam's pane hits for GlassModel::fromModes (Variant::Mixture, a reading z < z_max): the
/// range to the pane d_g, the mirrored and transmitted modes' expected ranges (+inf: none), the
/// three weights; out: p, and fix = 1 where a mode's truncation factor is not 1 (p then left for
/// the scalar fromModes).
struct GlassModeRays {
  const double *dg = nullptr, *en = nullptr, *er = nullptr, *wd = nullptr, *wn = nullptr, *wr = nullptr;
  double* p = nullptr;
  std::uint8_t* fix = nullptr;
};
using GlassModesFn = void (*)(const MixtureLanes& m, const GlassModeRays& r, std::size_t n);
void glassModesAvx2(const MixtureLanes& m, const GlassModeRays& r, std::size_t n);
void glassModesAvx512(const MixtureLanes& m, const GlassModeRays& r, std::size_t n);

}  // namespace glassmap::sensor::detail
