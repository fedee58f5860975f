#pragma once
/// First-hit ray casting against a VectorMap through a uniform-grid spatial index (DDA walk).
///
/// Hit rule (cast and castBruteForce agree bit for bit): the ray o + s*u hits segment a..b at
/// s > 0, s <= max_range, endpoints included (with a slack of 1e-12 of the segment's length, so
/// that rounding cannot open a gap at a corner where two segments meet). A ray parallel to a segment (collinear included)
/// does not hit it: a zero-thickness line seen edge-on has no face; the segments joined to its
/// ends are hit instead. A ray starting exactly on a segment does not hit that segment (s = 0 is
/// excluded); pass `skip` to ignore the pane a continued ray starts on, which also guards against
/// s being a rounding error above 0. Zero-length segments are never hit. Equal ranges resolve to
/// the lower segment id.

#include <cstdint>
#include <limits>
#include <vector>

#include "glassmap/geometry/vector_map.hpp"

namespace glassmap {

/// What a ray hit first.
struct RayHit {
  double range = std::numeric_limits<double>::infinity();  ///< distance to the hit [m]
  std::int32_t segment = -1;                               ///< index into VectorMap::segments, -1 if no hit
  Material material = Material::Wall;
  double incidence = 0.0;  ///< angle between ray and surface normal, [0, pi/2] [rad]
  bool hit() const { return segment >= 0; }
};

/// Instruction sets of RayCaster::castBatch. Auto: the best the CPU has (AVX-512 F+DQ, else
/// AVX2, else scalar), unless the environment variable GLASSMAP_RAY_ISA names one
/// (scalar / avx2 / avx512; one the CPU lacks falls back to the best it has).
enum class RayIsa { Auto, Scalar, Avx2, Avx512 };

/// Rays for RayCaster::castBatch as structure of arrays: ray i starts at (ox[i], oy[i]) [m] along
/// the unit direction (ux[i], uy[i]).
struct RayBatch {
  const double* ox = nullptr;
  const double* oy = nullptr;
  const double* ux = nullptr;
  const double* uy = nullptr;
  const double* max_range = nullptr;   ///< per ray [m], or null: `range` for every ray
  double range = 0.0;                  ///< max range of every ray when max_range is null [m]
  const std::int32_t* skip = nullptr;  ///< per ray segment id to ignore (-1: none), or null: none
  std::size_t size = 0;                ///< number of rays
};

/// Settings of the spatial index.
struct RayCasterOptions {
  double cell_size = 0.0;  ///< grid cell [m]; 0 picks one from the segment density
};

/// Immutable spatial index over a VectorMap's segments. Thread-safe for concurrent casts.
class RayCaster {
 public:
  explicit RayCaster(const VectorMap& map, RayCasterOptions options = {});

  /// First segment hit by the ray origin + s * (cos angle, sin angle), 0 < s <= max_range [m].
  /// `skip` is a segment id to ignore (the surface a continued ray starts on), -1 for none.
  RayHit cast(const Vec2& origin, double angle, double max_range, std::int32_t skip = -1) const;

  /// Same as cast(origin, angle, ...) with a precomputed unit direction `dir` (no sin/cos).
  RayHit cast(const Vec2& origin, const Vec2& dir, double max_range, std::int32_t skip = -1) const;

  /// cast() without the incidence angle (left 0; no atan): range, segment and material, for
  /// callers that need the angle only for some materials (see incidence()).
  RayHit castSurface(const Vec2& origin, const Vec2& dir, double max_range, std::int32_t skip = -1) const;

  /// Angle between unit direction `dir` and the normal of segment `segment`, [0, pi/2] [rad]: what
  /// cast() puts in RayHit::incidence.
  double incidence(std::int32_t segment, const Vec2& dir) const;

  /// Range only [m] of the first hit along unit direction `dir`; +infinity when nothing is hit
  /// within max_range. The fastest entry point (no incidence angle, no material).
  double castRange(const Vec2& origin, const Vec2& dir, double max_range, std::int32_t skip = -1) const;

  /// A scan: `count` beams at angles start_angle + k * step [rad]; writes each beam's first-hit
  /// range [m] to ranges[k], or `max_range` when nothing is hit. Directions come from one
  /// sin/cos and a rotation recurrence (relative error ~1e-15 per beam).
  void castScan(const Vec2& origin, double start_angle, double step, int count, double max_range, double* ranges) const;

  /// castSurface() of every ray of `rays`, several rays at a time with SIMD (one ray per lane,
  /// each walking its own cells; see RayIsa), bit for bit the single casts: range[i] is
  /// castRange()'s (+infinity for no hit), segment[i] (when not null) the segment id or -1.
  void castBatch(const RayBatch& rays, double* range, std::int32_t* segment = nullptr, RayIsa isa = RayIsa::Auto) const;
  /// castBatch for rays that come in coherent groups, e.g. one beam from many nearby particles:
  /// group g is rays [g == 0 ? 0 : group_end[g - 1], group_end[g]). A group shares one walk: its
  /// rays lie in a thin wedge (origins within a small disc, directions within a narrow cone), the
  /// wedge is swept slab by slab along its axis, and every segment listed in a cell the sweep
  /// touches is tested against the group's undecided rays at once; a ray is decided when the sweep
  /// has passed its best hit (nothing nearer can be left). The same hit test as the walk, the
  /// nearest hit and ties to the lower id: bit for bit castBatch. Groups that are not coherent
  /// (directions over 20 deg apart, origins outside the grid, non-finite input) go to castBatch.
  void castGroups(const RayBatch& rays, const std::size_t* group_end, std::size_t groups, double* range,
                  std::int32_t* segment = nullptr) const;
  /// The instruction set castBatch uses for RayIsa::Auto, and whether the CPU can run `isa`.
  static RayIsa bestIsa();
  static bool isaAvailable(RayIsa isa);
  static const char* isaName(RayIsa isa);

  /// Same as cast() by testing every segment: the reference for tests.
  RayHit castBruteForce(const Vec2& origin, double angle, double max_range, std::int32_t skip = -1) const;
  /// castBruteForce with a precomputed unit direction.
  RayHit castBruteForce(const Vec2& origin, const Vec2& dir, double max_range, std::int32_t skip = -1) const;

  const VectorMap& map() const { return map_; }
  double cellSize() const { return cell_; }
  int cellsX() const { return nx_; }  ///< grid columns
  int cellsY() const { return ny_; }  ///< grid rows
  /// Total entries in all cell lists (a segment counts once per cell it touches; lists are
  /// padded to even lengths).
  std::size_t cellEntries() const { return cell_items_.size(); }

 private:
  struct Best {
    double t;
    std::int32_t id;
  };
  template <bool kSkip>
  Best walk(double ox, double oy, double ux, double uy, double max_range, std::int32_t skip) const;
  Best walk(double ox, double oy, double ux, double uy, double max_range, std::int32_t skip) const;
  Best brute(double ox, double oy, double ux, double uy, double max_range, std::int32_t skip) const;
  RayHit finish(const Best& best, double ux, double uy) const;

  VectorMap map_;
  // Compact per-segment data for the hot loop: first endpoint and a -> b vector [m].
  struct Seg {
    double ax, ay, dx, dy;
  };
  // Two segments side by side (structure of arrays), for two-wide SIMD tests.
  struct alignas(16) SegPair {
    double ax[2], ay[2], dx[2], dy[2];
  };
  std::vector<Seg> segs_;                  // indexed by segment id (zero-length ones never enter cells)
  std::vector<Material> materials_;        // indexed by segment id
  std::vector<SegPair> items_;             // CSR payload: copies of each cell's segments, two by two
  std::vector<std::uint32_t> cell_items_;  // CSR payload: segment id of each lane (2 per pair)
  std::vector<std::uint32_t> cell_start_;  // CSR: cell -> [start, end) pairs in items_
  // The batch kernels' copy of the lists (src/geometry/ray_batch.hpp): one entry per segment
  // and cell, no padding; cells padded with a border ring whose span is -1.
  struct alignas(32) Seg4 {
    double ax, ay, dx, dy;
  };
  std::vector<Seg4> flat_;
  std::vector<std::int32_t> flat_ids_;
  std::vector<std::int64_t> spans_;  // (nx + 2) x (ny + 2): start | end << 32 into flat_
  double cell_ = 1.0;
  double inv_cell_ = 1.0;
  Vec2 origin_ = Vec2::Zero();  // lower-left corner of the grid [m]
  Vec2 top_ = Vec2::Zero();     // upper-right corner of the grid [m]
  int nx_ = 0, ny_ = 0;
};

}  // namespace glassmap
