#pragma once
/// A floorplan of line segments, each wall or glass with a thickness: the map every stage shares.

#include <algorithm>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Geometry>

#include "glassmap/core/pose2.hpp"

namespace glassmap {

/// What a segment is made of.
enum class Material : std::uint8_t { Wall = 0, Glass = 1 };

/// "wall" or "glass".
std::string_view toString(Material m);
/// Parses "wall"/"glass" (case-insensitive); throws Error otherwise.
Material parseMaterial(std::string_view s);

/// One straight piece of wall or glass. Endpoints in map frame [m].
/// (Stored as plain doubles, the layout of CGAL's Epick Segment_2; see geometry/cgal.hpp
/// for the conversion used by the stages that run CGAL algorithms.)
struct MapSegment {
  Vec2 a = Vec2::Zero();  ///< first endpoint [m]
  Vec2 b = Vec2::Zero();  ///< second endpoint [m]
  Material material = Material::Wall;
  double thickness = 0.1;  ///< pane or wall thickness [m]
  // Optional attributes filled by the vector stage (zero when unknown).
  double pane_angle = 0.0;    ///< pane normal direction in [0, pi) [rad]
  std::uint32_t support = 0;  ///< supporting grid cells
  double evidence = 0.0;      ///< mean per-cell evidence

  double length() const { return (b - a).norm(); }
  /// Unit direction a -> b (undefined for zero length).
  Vec2 direction() const { return (b - a).normalized(); }
  /// Point of the segment nearest to p (a for a zero-length segment).
  Vec2 closestPoint(const Vec2& p) const {
    const Vec2 ab = b - a;
    const double len2 = ab.squaredNorm();
    const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    return a + t * ab;
  }
  /// Distance from p to the segment [m].
  double distanceTo(const Vec2& p) const { return (p - closestPoint(p)).norm(); }
};

/// A floorplan: segments in a local metric frame (metres), one floor.
struct VectorMap {
  std::vector<MapSegment> segments;
  std::string name;  ///< optional label (file stem, scene name)

  Eigen::AlignedBox2d bounds() const;  ///< box of the segment ends [m]; empty without segments
  std::size_t count(Material m) const;
  /// Appends a segment a -> b of material m (other attributes at their defaults); returns it.
  MapSegment& add(const Vec2& a, const Vec2& b, Material m) {
    MapSegment& s = segments.emplace_back();
    s.a = a;
    s.b = b;
    s.material = m;
    return s;
  }
};

}  // namespace glassmap
