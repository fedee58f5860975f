#pragma once
/// Pictures of floorplans (PNG or SVG, Cairo): walls dark, glass blue, optional trajectory and points.

#include <cstdint>
#include <filesystem>
#include <vector>

#include "glassmap/core/pose2.hpp"
#include "glassmap/geometry/vector_map.hpp"

namespace glassmap {

/// A point to draw with its colour (0xRRGGBB).
struct ColoredPoint {
  Vec2 p;
  std::uint32_t rgb = 0x808080;
};

/// What to draw besides the segments.
struct FloorplanPicture {
  double pixels_per_metre = 40.0;    ///< scale [px/m]; lowered automatically past max_pixels
  double max_pixels = 4000.0;        ///< longest image side [px]
  double margin = 1.0;               ///< border around the content [m]
  std::vector<Vec2> trajectory;      ///< drawn as a red polyline
  std::vector<ColoredPoint> points;  ///< e.g. scan endpoints coloured by outcome
  double point_radius = 1.0;         ///< [px]
  bool legend = true;                ///< draw a scale bar and the colour legend
};

/// Writes a PNG or SVG (from the extension) of the floorplan, atomically.
void renderFloorplan(const std::filesystem::path& out, const VectorMap& map, const FloorplanPicture& picture = {});

}  // namespace glassmap
