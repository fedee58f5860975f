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

// Spans of cells idx in the lanes of `m`; the other lanes keep `src`.
inline vi gatherSpans(const std::int64_t* base, vi idx, vi m, vi src = vi{}) {
  return (vi)_mm512_mask_i64gather_epi64((__m512i)src, _mm512_movepi64_mask((__m512i)m), (__m512i)idx,
                                         reinterpret_cast<const long long*>(base), 8);
}
// Segment ids of entries idx (scalar loads: a gather is slower here).
inline vi gatherIds(const std::int32_t* ids, vi idx) {
  return vi{ids[idx[0]], ids[idx[1]], ids[idx[2]], ids[idx[3]], ids[idx[4]], ids[idx[5]], ids[idx[6]], ids[idx[7]]};
}
// Eight 32-byte segments (ax, ay, dx, dy) by index, transposed into ax, ay, dx, dy: plain loads
// and shuffles, several times faster than four gathers here.
inline void loadSegs(const double* segs, vi idx, vd& ax, vd& ay, vd& dx, vd& dy) {
  alignas(64) long at[8];
  __builtin_memcpy(at, &idx, sizeof at);
  auto row = [&](int j) { return _mm256_load_pd(segs + 4 * at[j]); };
  const __m512d z01 = _mm512_insertf64x4(_mm512_castpd256_pd512(row(0)), row(1), 1);
  const __m512d z23 = _mm512_insertf64x4(_mm512_castpd256_pd512(row(2)), row(3), 1);
  const __m512d z45 = _mm512_insertf64x4(_mm512_castpd256_pd512(row(4)), row(5), 1);
  const __m512d z67 = _mm512_insertf64x4(_mm512_castpd256_pd512(row(6)), row(7), 1);
  const __m512i lo = _mm512_set_epi64(13, 9, 5, 1, 12, 8, 4, 0);    // ax0-3 | ay0-3
  const __m512i hi = _mm512_set_epi64(15, 11, 7, 3, 14, 10, 6, 2);  // dx0-3 | dy0-3
  const __m512d a0 = _mm512_permutex2var_pd(z01, lo, z23), d0 = _mm512_permutex2var_pd(z01, hi, z23);
  const __m512d a1 = _mm512_permutex2var_pd(z45, lo, z67), d1 = _mm512_permutex2var_pd(z45, hi, z67);
  ax = (vd)_mm512_shuffle_f64x2(a0, a1, 0x44);  // lower 256 bits of each
  ay = (vd)_mm512_shuffle_f64x2(a0, a1, 0xEE);  // upper 256 bits of each
  dx = (vd)_mm512_shuffle_f64x2(d0, d1, 0x44);
  dy = (vd)_mm512_shuffle_f64x2(d0, d1, 0xEE);
}
// Results of the lanes in m: out_t[rid] = t, out_id[rid] = hit ? ids[e] : -1 (scattered).
inline void writeResults(double* out_t, std::int32_t* out_id, const std::int32_t* ids, unsigned m, vi rid, vd t, vi hit,
                         vi e) {
  const auto k = static_cast<__mmask8>(m);
  _mm512_mask_i64scatter_pd(out_t, k, (__m512i)rid, (__m512d)t, 8);
  if (out_id) {
    const __mmask8 h = _mm512_movepi64_mask((__m512i)hit) & k;
    const __m256i id = _mm512_mask_i64gather_epi32(_mm256_set1_epi32(-1), h, (__m512i)e, ids, 4);
    _mm512_mask_i64scatter_epi32(out_id, k, (__m512i)rid, id, 4);
  }
}
inline unsigned maskBits(vi m) { return static_cast<unsigned>(_mm512_movepi64_mask((__m512i)m)); }
inline vi laneMask(unsigned m) { return (vi)_mm512_movm_epi64(static_cast<__mmask8>(m)); }
inline vi ranks(unsigned m) {
  return (vi)_mm512_maskz_expand_epi64(static_cast<__mmask8>(m), _mm512_set_epi64(7, 6, 5, 4, 3, 2, 1, 0));
}
inline vd expandLoad(vd src, unsigned m, const double* p) {
  return (vd)_mm512_mask_expandloadu_pd((__m512d)src, static_cast<__mmask8>(m), p);
}
inline vi expandLoadi(vi src, unsigned m, const std::int64_t* p) {
  return (vi)_mm512_mask_expandloadu_epi64((__m512i)src, static_cast<__mmask8>(m), p);
}
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

double testSegmentAvx512(double* best, std::int64_t* id, const double* ox, const double* oy, const double* ux,
                         const double* uy, const std::int64_t* skip, std::size_t n, double ax, double ay, double dx,
                         double dy, std::int64_t seg_id) {
  return testSegmentLanes(best, id, ox, oy, ux, uy, skip, n, ax, ay, dx, dy, seg_id);
}

void groupSetupAvx512(const double* ox, const double* oy, const double* ux, const double* uy, const double* max_range,
                      double* best, std::size_t n, std::size_t padded, GroupStats& stats) {
  groupSetupLanes(ox, oy, ux, uy, max_range, best, n, padded, stats);
}

void groupConeAvx512(const double* ox, const double* oy, const double* ux, const double* uy, std::size_t n,
                     std::size_t padded, double cx, double cy, double ax, double ay, double& cos_a, double& radius2) {
  groupConeLanes(ox, oy, ux, uy, n, padded, cx, cy, ax, ay, cos_a, radius2);
}

}  // namespace glassmap::detail
#endif
