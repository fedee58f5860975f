#pragma once
/// Internal: the view of a RayCaster's index that the SIMD batch kernels read, and the kernels.
/// Each kernel is compiled in its own source file with its instruction set (ray_batch_avx2.cpp,
/// ray_batch_avx512.cpp); ray_batch.cpp picks one at run time.

#include <cstddef>
#include <cstdint>

namespace glassmap::detail {

/// The grid as the kernels see it. The cell spans are padded with one ring of border cells
/// (width nx + 2) whose span is negative: a walk that steps onto one has left the grid.
struct PacketGrid {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< grid box [m]
  double cell = 1, inv_cell = 1;          ///< cell size [m] and its inverse [1/m]
  int nx = 0, ny = 0;                     ///< cells inside the border
  const std::int64_t* spans = nullptr;    ///< padded cell -> start | end << 32 into segs, or -1
  const double* segs = nullptr;           ///< all cell lists (ax, ay, dx, dy per entry, 32-byte aligned)
  const std::int32_t* ids = nullptr;      ///< segment id of each entry of segs
};

/// Rays as structure of arrays; the kernels write out_t[i] (the hit's range, +inf for no hit) and,
/// when out_id is not null, out_id[i] (segment id, -1 for no hit), bit for bit as RayCaster::walk.
struct PacketRays {
  const double *ox = nullptr, *oy = nullptr, *ux = nullptr, *uy = nullptr;
  const double* max_range = nullptr;  ///< per ray, or null: `range` for all
  double range = 0;
  const std::int32_t* skip = nullptr;  ///< per ray, or null: none
  std::size_t n = 0;
};

/// castGroups' inner loop (ray_coherent.cpp): segment (ax, ay) + v (dx, dy), id seg_id, against
/// rays [0, n) (n a multiple of the lanes: 4 or 8), updating best[k] / id[k] (nearest, ties to the
/// lower id) with the walk's hit test. Returns the smallest range it wrote to best (+inf: none).
using TestSegmentFn = double (*)(double* best, std::int64_t* id, const double* ox, const double* oy, const double* ux,
                                 const double* uy, const std::int64_t* skip, std::size_t n, double ax, double ay,
                                 double dx, double dy, std::int64_t seg_id);
double testSegmentAvx2(double* best, std::int64_t* id, const double* ox, const double* oy, const double* ux,
                       const double* uy, const std::int64_t* skip, std::size_t n, double ax, double ay, double dx,
                       double dy, std::int64_t seg_id);
double testSegmentAvx512(double* best, std::int64_t* id, const double* ox, const double* oy, const double* ux,
                         const double* uy, const std::int64_t* skip, std::size_t n, double ax, double ay, double dx,
                         double dy, std::int64_t seg_id);

/// castGroups' set-up of one group: slots [0, padded) (padded a multiple of the lanes) hold its
/// rays, the first n real ones (padding slots finite). Writes best[k] = ray_caster.cpp's
/// acceptLimit(max_range[k]) for the real rays (-inf for padding), and the group's sums of origins
/// and directions, largest (capped at 1e300) and smallest max range, and whether every real ray is
/// finite, a unit direction (|u|^2 within 1e-9 of 1) with a positive max range, inside the box.
struct GroupStats {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< in: the grid's box [m]
  double sx = 0, sy = 0, su = 0, sv = 0;  ///< out: sums of ox, oy, ux, uy
  double max_range = 0;                   ///< out [m]
  double min_range = __builtin_inf();     ///< out [m]
  bool ok = true;                         ///< out
};
using GroupSetupFn = void (*)(const double* ox, const double* oy, const double* ux, const double* uy,
                              const double* max_range, double* best, std::size_t n, std::size_t padded,
                              GroupStats& stats);
/// Then its cone and disc about the axis through (cx, cy) along (ax, ay): cos_a = min(1, min of
/// u . a), radius2 = max(0, max of |o - c|^2) over the real rays.
using GroupConeFn = void (*)(const double* ox, const double* oy, const double* ux, const double* uy, std::size_t n,
                             std::size_t padded, double cx, double cy, double ax, double ay, double& cos_a,
                             double& radius2);
void groupSetupAvx2(const double* ox, const double* oy, const double* ux, const double* uy, const double* max_range,
                    double* best, std::size_t n, std::size_t padded, GroupStats& stats);
void groupSetupAvx512(const double* ox, const double* oy, const double* ux, const double* uy, const double* max_range,
                      double* best, std::size_t n, std::size_t padded, GroupStats& stats);
void groupConeAvx2(const double* ox, const double* oy, const double* ux, const double* uy, std::size_t n,
                   std::size_t padded, double cx, double cy, double ax, double ay, double& cos_a, double& radius2);
void groupConeAvx512(const double* ox, const double* oy, const double* ux, const double* uy, std::size_t n,
                     std::size_t padded, double cx, double cy, double ax, double ay, double& cos_a, double& radius2);

void castPacketsAvx2(const PacketGrid& grid, const PacketRays& rays, double* out_t, std::int32_t* out_id);
void castPacketsAvx512(const PacketGrid& grid, const PacketRays& rays, double* out_t, std::int32_t* out_id);

}  // namespace glassmap::detail
