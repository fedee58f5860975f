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
};

/// p[k] for expected range e[k], k in [0, n). Where the hit density's truncation factor is not 1
/// (e within 6 sigma of 0 or of z_max) fix[k] = 1 and p[k] is left for the caller to compute with
/// Mixture::probability; else fix[k] = 0.
using MixtureLanesFn = void (*)(const MixtureLanes& m, const double* e, double* p, std::uint8_t* fix, std::size_t n);
void mixtureLanesAvx2(const MixtureLanes& m, const double* e, double* p, std::uint8_t* fix, std::size_t n);
void mixtureLanesAvx512(const MixtureLanes& m, const double* e, double* p, std::uint8_t* fix, std::size_t n);

}  // namespace glassmap::sensor::detail
