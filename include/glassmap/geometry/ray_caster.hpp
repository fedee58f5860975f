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
  double cell_ = 1.0;
  double inv_cell_ = 1.0;
  Vec2 origin_ = Vec2::Zero();  // lower-left corner of the grid [m]
  Vec2 top_ = Vec2::Zero();     // upper-right corner of the grid [m]
  int nx_ = 0, ny_ = 0;
};

}  // namespace glassmap
