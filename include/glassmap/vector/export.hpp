#pragma once
/// Writing a floorplan in every format users take home, and reading label rasters for vectorize().

#include <filesystem>
#include <string>
#include <vector>

#include "glassmap/geometry/vector_map.hpp"
#include "glassmap/io/floorplan_extras.hpp"
#include "glassmap/io/labels_raster.hpp"
#include "glassmap/vector/label_grid.hpp"

namespace glassmap::vector {

/// Extensions exportFloorplan writes: gpkg geojson json shp fgb dxf (GDAL, see io/floorplan.hpp),
/// svg png (picture, io/render_floorplan.hpp), pdf (to scale, io/render_pdf.hpp).
const std::vector<std::string>& exportFormats();

/// The set `glassmap map` and `glassmap vectorize` write: gpkg geojson dxf svg png.
const std::vector<std::string>& defaultFloorplanSet();

/// True if the path's extension (case-insensitive) is one of exportFormats().
bool isExportFormat(const std::filesystem::path& path);

/// Writes the map in the format of the path's extension, atomically, with the extra layers where
/// the format holds them (GPKG, GeoJSON, DXF; pictures draw clutter and doors too) and in the
/// building's CRS when `georef` is given. Throws Error for other extensions.
void exportFloorplan(const std::filesystem::path& path, const VectorMap& map, const FloorplanExtras& extras = {},
                     const FloorplanGeoref* georef = nullptr);

/// Writes <stem>.<ext> for every extension, in order; returns the paths written. When one fails
/// (Error), the files this call wrote are removed before the error goes on: no partial set.
/// pipeline::writeMapFiles calls writeFloorplanSet(dir / "floorplan", result.floorplan.map).
std::vector<std::filesystem::path> writeFloorplanSet(const std::filesystem::path& stem, const VectorMap& map,
                                                     const std::vector<std::string>& extensions = defaultFloorplanSet(),
                                                     const FloorplanExtras& extras = {},
                                                     const FloorplanGeoref* georef = nullptr);

/// The label grid of a raster read by io's readLabelRaster (5-degree glass bins, no evidence).
LabelGrid toLabelGrid(const LabelRaster& raster);

}  // namespace glassmap::vector
