#include "glassmap/vector/export.hpp"

#include <algorithm>
#include <cctype>

#include "glassmap/core/error.hpp"
#include "glassmap/io/floorplan.hpp"
#include "glassmap/io/render_floorplan.hpp"
#include "glassmap/io/render_pdf.hpp"

namespace glassmap::vector {
namespace {

std::string lowerExtension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  if (!ext.empty() && ext.front() == '.') ext.erase(0, 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

}  // namespace

const std::vector<std::string>& exportFormats() {
  static const std::vector<std::string> formats = {"gpkg", "geojson", "json", "shp", "fgb", "dxf", "svg", "png", "pdf"};
  return formats;
}

const std::vector<std::string>& defaultFloorplanSet() {
  static const std::vector<std::string> formats = {"gpkg", "geojson", "dxf", "svg", "png"};
  return formats;
}

bool isExportFormat(const std::filesystem::path& path) {
  const std::string ext = lowerExtension(path);
  const auto& f = exportFormats();
  return std::find(f.begin(), f.end(), ext) != f.end();
}

void exportFloorplan(const std::filesystem::path& path, const VectorMap& map, const FloorplanExtras& extras,
                     const FloorplanGeoref* georef) {
  const std::string ext = lowerExtension(path);
  if (ext == "svg" || ext == "png" || ext == "pdf") {
    VectorMap placed = map;  // pictures: in building coordinates when georeferenced
    if (georef)
      for (MapSegment& s : placed.segments) s.a = georef->origin * s.a, s.b = georef->origin * s.b;
    if (ext == "pdf") return renderFloorplanPdf(path, placed);
    FloorplanPicture picture;
    picture.pixels_per_metre = 50.0;
    renderFloorplan(path, placed, picture);
  } else if (isExportFormat(path)) {
    writeFloorplan(path, map, extras, georef);
  } else {
    throw Error("unknown floorplan format '." + ext +
                    "' (expected .gpkg, .geojson, .json, .shp, .fgb, .dxf, .svg, .png or .pdf)",
                path.string());
  }
}

std::vector<std::filesystem::path> writeFloorplanSet(const std::filesystem::path& stem, const VectorMap& map,
                                                     const std::vector<std::string>& extensions,
                                                     const FloorplanExtras& extras, const FloorplanGeoref* georef) {
  std::vector<std::filesystem::path> written;
  try {
    for (const std::string& ext : extensions) {
      std::filesystem::path p = stem;
      p += "." + ext;
      // Pictures of an empty map have nothing to show; the vector formats are still written.
      if (map.segments.empty() && (ext == "svg" || ext == "png" || ext == "pdf")) continue;
      exportFloorplan(p, map, extras, georef);
      written.push_back(p);
    }
  } catch (...) {
    // A set is whole or not there: a failed file (a full disk) takes the ones before it along.
    std::error_code ec;
    for (const auto& p : written) std::filesystem::remove(p, ec);
    throw;
  }
  return written;
}

LabelGrid toLabelGrid(const LabelRaster& raster) {
  LabelGrid g;
  g.width = raster.width;
  g.height = raster.height;
  g.resolution = raster.resolution;
  g.origin = raster.origin;
  g.codes = raster.codes;
  g.validate();
  return g;
}

}  // namespace glassmap::vector
