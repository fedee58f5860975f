#pragma once
/// First-hit ray casting against a VectorMap through a uniform-grid spatial index (DDA walk).

#include <cstdint>
#include <limits>
#include <vector>

#include "glassmap/geometry/vector_map.hpp"

namespace glassmap {

/// What a ray hit first.
struct RayHit {
  double range = std::numeric_limits<double>::infinity();  ///< distance to the hit [m]
  std::int32_t segment = -1;     ///< index into VectorMap::segments, -1 if no hit
  Material material = Material::Wall;
  double incidence = 0.0;        ///< angle between ray and surface normal, [0, pi/2] [rad]
  bool hit() const { return segment >= 0; }
};

/// Settings of the spatial index.
struct RayCasterOptions {
  double cell_size = 0.0;  ///< grid cell [m]; 0 picks one from the segment lengths
};

/// Immutable spatial index over a VectorMap's segments. Thread-safe for concurrent casts.
class RayCaster {
 public:
  explicit RayCaster(const VectorMap& map, RayCasterOptions options = {});

  /// First segment hit by the ray origin + s * (cos angle, sin angle), 0 < s <= max_range [m].
  /// `skip` is a segment id to ignore (the surface a continued ray starts on), -1 for none.
  RayHit cast(const Vec2& origin, double angle, double max_range,
              std::int32_t skip = -1) const;

  /// Same as cast() by testing every segment: the reference for tests.
  RayHit castBruteForce(const Vec2& origin, double angle, double max_range,
                        std::int32_t skip = -1) const;

  const VectorMap& map() const { return map_; }
  double cellSize() const { return cell_; }

 private:
  VectorMap map_;
  // Compact per-segment data for the hot loop.
  struct Seg { double ax, ay, dx, dy; };
  std::vector<Seg> segs_;
  double cell_ = 1.0;
  Vec2 origin_ = Vec2::Zero();
  int nx_ = 0, ny_ = 0;
  std::vector<std::uint32_t> cell_start_;  // CSR: cell -> [start, end) into cell_items_
  std::vector<std::uint32_t> cell_items_;
};

}  // namespace glassmap
