// The beam-model mixture on 4 lanes (AVX2 + libmvec); see mixture_lanes.hpp.
#include "mixture_lanes.hpp"

#if defined(__AVX2__)
#include <immintrin.h>

extern "C" __m256d _ZGVdN4v_exp(__m256d);
extern "C" __m256d _ZGVdN4v_expm1(__m256d);
extern "C" __m256d _ZGVdN4v_atan(__m256d);

namespace glassmap::sensor::detail {
namespace {

constexpr int W = 4;
typedef double vd __attribute__((vector_size(32)));
typedef long vi __attribute__((vector_size(32)));
inline vd vexp(vd x) { return (vd)_ZGVdN4v_exp((__m256d)x); }
inline vd vexpm1(vd x) { return (vd)_ZGVdN4v_expm1((__m256d)x); }
inline vd vatan(vd x) { return (vd)_ZGVdN4v_atan((__m256d)x); }

#include "mixture_lanes.inc"

}  // namespace

void mixtureLanesAvx2(const MixtureLanes& m, const double* e, double* p, std::uint8_t* fix, std::size_t n) {
  mixtureLanesBody(m, e, p, fix, n);
}
void glassWeightsAvx2(const GlassWeightLanes& m, const GlassWeightRays& r, std::size_t n) { glassWeightsBody(m, r, n); }
void glassModesAvx2(const MixtureLanes& m, const GlassModeRays& r, std::size_t n) { glassModesBody(m, r, n); }

}  // namespace glassmap::sensor::detail
#endif
