// The batch ray caster for AVX2: 4 rays per step (ray_batch_kernel.inc). Compiled with -mavx2
// and -ffp-contract=off; only called when the CPU has AVX2 (ray_batch.cpp checks).
#include "ray_batch.hpp"

#if defined(__AVX2__)
#include <immintrin.h>

namespace glassmap::detail {
namespace {

constexpr int W = 4;
typedef double vd __attribute__((vector_size(32)));
typedef long vi __attribute__((vector_size(32)));
typedef unsigned long vu __attribute__((vector_size(32)));

inline vi gatherSpans(const std::int64_t* base, vi idx) {
  return (vi)_mm256_i64gather_epi64(reinterpret_cast<const long long*>(base), (__m256i)idx, 8);
}
inline vi gatherIds(const std::int32_t* ids, vi idx) {
  return (vi)_mm256_cvtepi32_epi64(_mm256_i64gather_epi32(reinterpret_cast<const int*>(ids), (__m256i)idx, 4));
}
// Four 32-byte segments, transposed into ax, ay, dx, dy.
inline void loadSegs(const double* segs, vi idx, vd& ax, vd& ay, vd& dx, vd& dy) {
  const __m256d r0 = _mm256_load_pd(segs + 4 * idx[0]), r1 = _mm256_load_pd(segs + 4 * idx[1]);
  const __m256d r2 = _mm256_load_pd(segs + 4 * idx[2]), r3 = _mm256_load_pd(segs + 4 * idx[3]);
  const __m256d t0 = _mm256_unpacklo_pd(r0, r1), t1 = _mm256_unpackhi_pd(r0, r1);
  const __m256d t2 = _mm256_unpacklo_pd(r2, r3), t3 = _mm256_unpackhi_pd(r2, r3);
  ax = (vd)_mm256_permute2f128_pd(t0, t2, 0x20);
  dx = (vd)_mm256_permute2f128_pd(t0, t2, 0x31);
  ay = (vd)_mm256_permute2f128_pd(t1, t3, 0x20);
  dy = (vd)_mm256_permute2f128_pd(t1, t3, 0x31);
}
inline unsigned maskBits(vi m) { return static_cast<unsigned>(_mm256_movemask_pd((__m256d)m)); }
inline vd truncd(vd x) { return (vd)_mm256_round_pd((__m256d)x, _MM_FROUND_TO_ZERO | _MM_FROUND_NO_EXC); }
inline vi toInt(vd x) { return (vi)_mm256_cvtepi32_epi64(_mm256_cvttpd_epi32((__m256d)x)); }

#include "ray_batch_kernel.inc"

}  // namespace

void castPacketsAvx2(const PacketGrid& grid, const PacketRays& rays, double* out_t, std::int32_t* out_id) {
  if (rays.skip)
    castPackets<true>(grid, rays, out_t, out_id);
  else
    castPackets<false>(grid, rays, out_t, out_id);
}

}  // namespace glassmap::detail
#endif
