// The beam-model mixture on 8 lanes (AVX-512 + libmvec); see mixture_lanes.hpp.
#include "mixture_lanes.hpp"

#if defined(__AVX512F__) && defined(__AVX512DQ__)
// GCC 12's AVX-512 headers start some intrinsics from a deliberately undefined vector.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <immintrin.h>

extern "C" __m512d _ZGVeN8v_exp(__m512d);
extern "C" __m512d _ZGVeN8v_expm1(__m512d);
extern "C" __m512d _ZGVeN8v_atan(__m512d);

namespace glassmap::sensor::detail {
namespace {

constexpr int W = 8;
typedef double vd __attribute__((vector_size(64)));
typedef long vi __attribute__((vector_size(64)));
inline vd vexp(vd x) { return (vd)_ZGVeN8v_exp((__m512d)x); }
inline vd vexpm1(vd x) { return (vd)_ZGVeN8v_expm1((__m512d)x); }
inline vd vatan(vd x) { return (vd)_ZGVeN8v_atan((__m512d)x); }

#include "mixture_lanes.inc"

}  // namespace

void mixtureLanesAvx512(const MixtureLanes& m, const double* e, double* p, std::uint8_t* fix, std::size_t n) {
  mixtureLanesBody(m, e, p, fix, n);
}
void glassWeightsAvx512(const GlassWeightLanes& m, const GlassWeightRays& r, std::size_t n) {
  glassWeightsBody(m, r, n);
}
void glassModesAvx512(const MixtureLanes& m, const GlassModeRays& r, std::size_t n) { glassModesBody(m, r, n); }

}  // namespace glassmap::sensor::detail
#endif
