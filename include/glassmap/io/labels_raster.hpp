#pragma once
/// Glass label grids as GeoTIFF: one uint8 code per cell (0 unknown, 1 empty, 2 occupied,
/// 10 + k glass with pane normal at k * 5 deg), local metric coordinates, a colour table for QGIS.

#include <cstdint>
#include <filesystem>
#include <vector>

#include "glassmap/core/pose2.hpp"

namespace glassmap {

/// A label-code raster. Row 0 is the BOTTOM row (as OccupancyGridMap); the file stores it north-up.
struct LabelRaster {
  int width = 0;                    ///< cells along x
  int height = 0;                   ///< cells along y
  double resolution = 0.05;         ///< cell size [m]
  Vec2 origin = Vec2::Zero();       ///< lower-left corner of cell (0, 0) in the map frame [m]
  std::vector<std::uint8_t> codes;  ///< width * height codes, index = row * width + col
};

/// Writes a single-band Byte GeoTIFF (DEFLATE), atomically. Throws Error on a size mismatch or a
/// GDAL failure.
void writeLabelRaster(const std::filesystem::path& tif, const LabelRaster& raster);

/// Reads a raster written by writeLabelRaster (or any single-band Byte raster with a north-up or
/// south-up geotransform and square pixels). Throws Error naming the file otherwise.
LabelRaster readLabelRaster(const std::filesystem::path& tif);

}  // namespace glassmap
