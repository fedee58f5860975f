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

// Spans of cells idx in the lanes of `m`; the other lanes keep `src` (four loads: faster than
// a gather here).
inline vi gatherSpans(const std::int64_t* base, vi idx, vi m, vi src = vi{}) {
  const vi at = idx & m;  // lanes outside m read cell 0
  const vi v = {base[at[0]], base[at[1]], base[at[2]], base[at[3]]};
  return m ? v : src;
}
// Segment ids of entries idx (scalar loads: a gather is slower here).
inline vi gatherIds(const std::int32_t* ids, vi idx) { return vi{ids[idx[0]], ids[idx[1]], ids[idx[2]], ids[idx[3]]}; }
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
// Results of the lanes in m: out_t[rid] = t, out_id[rid] = hit ? ids[e] : -1.
inline void writeResults(double* out_t, std::int32_t* out_id, const std::int32_t* ids, unsigned m, vi rid, vd t, vi hit,
                         vi e) {
  for (unsigned bits = m; bits; bits &= bits - 1) {
    const int j = __builtin_ctz(bits);
    out_t[rid[j]] = t[j];
    if (out_id) out_id[rid[j]] = hit[j] ? ids[e[j]] : -1;
  }
}
inline unsigned maskBits(vi m) { return static_cast<unsigned>(_mm256_movemask_pd((__m256d)m)); }

// Per 4-bit lane mask m: each lane's all-ones mask, its rank among the lanes of m, and the
// dword permutation that moves element rank(j) of a vector into lane j (an expanding load).
struct ExpandTables {
  alignas(32) long mask[16][4];
  alignas(32) long rank[16][4];
  alignas(32) int perm[16][8];
  constexpr ExpandTables() : mask{}, rank{}, perm{} {
    for (int m = 0; m < 16; ++m) {
      int r = 0;
      for (int j = 0; j < 4; ++j) {
        const bool in = (m >> j) & 1;
        mask[m][j] = in ? -1 : 0;
        rank[m][j] = in ? r : 0;
        perm[m][2 * j] = in ? 2 * r : 2 * j;
        perm[m][2 * j + 1] = in ? 2 * r + 1 : 2 * j + 1;
        r += in;
      }
    }
  }
};
constexpr ExpandTables kExpand;

inline vi laneMask(unsigned m) { return *reinterpret_cast<const vi*>(kExpand.mask[m]); }
inline vi ranks(unsigned m) { return *reinterpret_cast<const vi*>(kExpand.rank[m]); }
inline __m256i expandRaw(unsigned m, const void* p) {
  const __m256i ctl = _mm256_load_si256(reinterpret_cast<const __m256i*>(kExpand.perm[m]));
  return _mm256_permutevar8x32_epi32(_mm256_loadu_si256(static_cast<const __m256i*>(p)), ctl);
}
inline vd expandLoad(vd src, unsigned m, const double* p) {
  return (vd)_mm256_blendv_pd((__m256d)src, _mm256_castsi256_pd(expandRaw(m, p)), (__m256d)laneMask(m));
}
inline vi expandLoadi(vi src, unsigned m, const std::int64_t* p) {
  return (vi)_mm256_blendv_pd((__m256d)src, _mm256_castsi256_pd(expandRaw(m, p)), (__m256d)laneMask(m));
}
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

double testSegmentAvx2(double* best, std::int64_t* id, const double* ox, const double* oy, const double* ux,
                       const double* uy, const std::int64_t* skip, std::size_t n, double ax, double ay, double dx,
                       double dy, std::int64_t seg_id) {
  return testSegmentLanes(best, id, ox, oy, ux, uy, skip, n, ax, ay, dx, dy, seg_id);
}

void groupSetupAvx2(const double* ox, const double* oy, const double* ux, const double* uy, const double* max_range,
                    double* best, std::size_t n, std::size_t padded, GroupStats& stats) {
  groupSetupLanes(ox, oy, ux, uy, max_range, best, n, padded, stats);
}

void groupConeAvx2(const double* ox, const double* oy, const double* ux, const double* uy, std::size_t n,
                   std::size_t padded, double cx, double cy, double ax, double ay, double& cos_a, double& radius2) {
  groupConeLanes(ox, oy, ux, uy, n, padded, cx, cy, ax, ay, cos_a, radius2);
}

}  // namespace glassmap::detail
#endif
