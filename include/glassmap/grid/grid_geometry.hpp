#pragma once
/// Geometry of a 2D grid map: cell size, origin and cell indexing. Row 0 is the bottom row (ROS).

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "glassmap/core/pose2.hpp"

namespace glassmap::grid {

/// Integer cell coordinates (x = column, y = row from the bottom).
struct CellIndex {
  int x = 0;
  int y = 0;
  bool operator==(const CellIndex&) const = default;
};

/// Cell size, origin (map-frame position of the lower-left corner of cell (0, 0)) and extent.
struct GridGeometry {
  double resolution = 0.05;    ///< cell size [m]
  Vec2 origin = Vec2::Zero();  ///< lower-left corner of cell (0, 0) in the map frame [m]
  int width = 0;               ///< cells along x
  int height = 0;              ///< cells along y

  std::size_t cells() const { return static_cast<std::size_t>(width) * static_cast<std::size_t>(height); }
  bool contains(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height; }
  bool contains(const CellIndex& c) const { return contains(c.x, c.y); }
  /// Linear index y * width + x (row 0 = bottom).
  std::size_t index(int x, int y) const {
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x);
  }
  std::size_t index(const CellIndex& c) const { return index(c.x, c.y); }
  /// Cell of linear index i.
  CellIndex cellOf(std::size_t i) const {
    return {static_cast<int>(i % static_cast<std::size_t>(width)),
            static_cast<int>(i / static_cast<std::size_t>(width))};
  }
  /// Cell containing map-frame point p (may lie outside the grid).
  CellIndex cellAt(const Vec2& p) const {
    return {static_cast<int>(std::floor((p.x() - origin.x()) / resolution)),
            static_cast<int>(std::floor((p.y() - origin.y()) / resolution))};
  }
  /// Map-frame centre of cell (x, y) [m].
  Vec2 center(int x, int y) const { return origin + Vec2((x + 0.5) * resolution, (y + 0.5) * resolution); }
  /// Map-frame upper-right corner of the grid [m].
  Vec2 maxCorner() const { return origin + Vec2(width * resolution, height * resolution); }
};

/// The smallest grid of cell size `resolution` covering the box [min, max] plus `margin` [m] on each
/// side; the origin is snapped to a multiple of the resolution.
GridGeometry coveringGeometry(const Vec2& min, const Vec2& max, double resolution, double margin = 0.0);

}  // namespace glassmap::grid
