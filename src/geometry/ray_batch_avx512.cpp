// The batch ray caster for AVX-512 (F + DQ): 8 rays per step (ray_batch_kernel.inc). Compiled
// with -mavx512f -mavx512dq and -ffp-contract=off; only called when the CPU has both
// (ray_batch.cpp checks).
#include "ray_batch.hpp"

#if defined(__AVX512F__) && defined(__AVX512DQ__)
// GCC 12's AVX-512 headers start some intrinsics from a deliberately undefined vector
// (_mm512_undefined_*), which -Wmaybe-uninitialized reports at every use.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <immintrin.h>

namespace glassmap::detail {
namespace {

constexpr int W = 8;
typedef double vd __attribute__((vector_size(64)));
typedef long vi __attribute__((vector_size(64)));
typedef unsigned long vu __attribute__((vector_size(64)));

inline vi gatherSpans(const std::int64_t* base, vi idx) {
  return (vi)_mm512_i64gather_epi64((__m512i)idx, reinterpret_cast<const long long*>(base), 8);
}
inline vi gatherIds(const std::int32_t* ids, vi idx) {
  return (vi)_mm512_cvtepi32_epi64(_mm512_i64gather_epi32((__m512i)idx, reinterpret_cast<const int*>(ids), 4));
}
inline void loadSegs(const double* segs, vi idx, vd& ax, vd& ay, vd& dx, vd& dy) {
  const __m512i off = (__m512i)(idx << 2);  // 4 doubles per segment
  const double* base = segs;
  ax = (vd)_mm512_i64gather_pd(off, base, 8);
  ay = (vd)_mm512_i64gather_pd(off, base + 1, 8);
  dx = (vd)_mm512_i64gather_pd(off, base + 2, 8);
  dy = (vd)_mm512_i64gather_pd(off, base + 3, 8);
}
inline unsigned maskBits(vi m) { return static_cast<unsigned>(_mm512_movepi64_mask((__m512i)m)); }
inline vd truncd(vd x) { return (vd)_mm512_roundscale_pd((__m512d)x, _MM_FROUND_TO_ZERO | _MM_FROUND_NO_EXC); }
inline vi toInt(vd x) { return (vi)_mm512_cvttpd_epi64((__m512d)x); }

#include "ray_batch_kernel.inc"

}  // namespace

void castPacketsAvx512(const PacketGrid& grid, const PacketRays& rays, double* out_t, std::int32_t* out_id) {
  if (rays.skip)
    castPackets<true>(grid, rays, out_t, out_id);
  else
    castPackets<false>(grid, rays, out_t, out_id);
}

}  // namespace glassmap::detail
#endif
