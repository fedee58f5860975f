#pragma once
/// The vector stage's input: a raster of cell codes (DESIGN.md's GeoTIFF codes) with optional
/// per-cell evidence. Kept free of the grid/glass types so that vectorisation runs on any label
/// raster (a mapped labels.tif, a synthetic test grid, a rasterised floorplan).

#include <cstdint>
#include <vector>

#include "glassmap/core/labels.hpp"
#include "glassmap/core/pose2.hpp"
#include "glassmap/geometry/vector_map.hpp"

namespace glassmap::vector {

// Codes: glassmap/core/labels.hpp (0 unknown, 1 empty, 2..9 occupied, 10 + k glass).

/// A label raster. Row 0 is the bottom row; cell (x, y) has linear index y * width + x.
struct LabelGrid {
  int width = 0;                    ///< cells along x
  int height = 0;                   ///< cells along y
  double resolution = 0.05;         ///< cell size [m]
  Vec2 origin = Vec2::Zero();       ///< lower-left corner of cell (0, 0) in the map frame [m]
  double angle_bin_deg = 5.0;       ///< glass code 10 + k has its pane normal at k * bin [deg]
  std::vector<std::uint8_t> codes;  ///< [y * width + x] code: 0 unknown, 1 empty, 2 occupied, 10 + k glass
  std::vector<float> evidence;      ///< optional [cell] confidence of the cell's code in [0, 1]; empty if none

  std::size_t cells() const { return static_cast<std::size_t>(width) * static_cast<std::size_t>(height); }
  std::uint8_t code(int x, int y) const { return codes[static_cast<std::size_t>(y) * width + x]; }
  /// Map-frame centre of cell (x, y) [m].
  Vec2 center(int x, int y) const { return origin + Vec2((x + 0.5) * resolution, (y + 0.5) * resolution); }
  /// Pane normal of a glass code in [0, pi) [rad].
  double normalOf(std::uint8_t glass_code) const;
  /// Throws Error unless sizes agree and resolution and bin width are positive.
  void validate() const;
};

/// A blank grid (all unknown) of the given size covering [origin, origin + size * resolution].
LabelGrid makeLabelGrid(int width, int height, double resolution, const Vec2& origin = Vec2::Zero());

/// Glass code of a pane normal [rad] for bins of bin_deg degrees (normal taken modulo pi).
std::uint8_t glassCodeOf(double normal, double bin_deg = 5.0);

/// Draws a floorplan into a grid: every cell within thickness/2 + half a cell of a segment gets
/// its material's code (glass by its normal). For tests and for scoring rasters against floorplans.
void rasterize(LabelGrid& grid, const VectorMap& map, double min_thickness = 0.0);

}  // namespace glassmap::vector
