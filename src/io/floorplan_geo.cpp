// Coordinates of floorplans read through GDAL: what a GeoJSON says about its CRS before its
// features, and geographic coordinates to local metres.
#include <ogr_spatialref.h>

#include <fstream>
#include <memory>
#include <string>

#include "floorplan_detail.hpp"
#include "glassmap/core/error.hpp"

namespace glassmap::io_detail {

namespace fs = std::filesystem;

GeoJsonHead geoJsonHead(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string head(64 * 1024, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  const std::size_t features = head.find("\"features\"");
  const std::string before = head.substr(0, features);
  return {before.find("\"crs\"") != std::string::npos, before.find(kGeoJsonMarker) != std::string::npos};
}

// A transformation from a geographic CRS to metres of a transverse Mercator centred on (lon, lat):
// a local metric frame in which a building's plan keeps its shape to well under a millimetre.
std::unique_ptr<OGRCoordinateTransformation> toLocalMetres(const OGRSpatialReference& geographic, double lon,
                                                           double lat, const std::string& file) {
  OGRSpatialReference local;
  local.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  if (local.SetWellKnownGeogCS("WGS84") != OGRERR_NONE || local.SetTM(lat, lon, 1.0, 0.0, 0.0) != OGRERR_NONE)
    throw Error("cannot build a local transverse Mercator frame", file);
  OGRSpatialReference src(geographic);
  src.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  std::unique_ptr<OGRCoordinateTransformation> ct(OGRCreateCoordinateTransformation(&src, &local));
  if (!ct) throw Error("cannot transform the plan's geographic coordinates to metres (PROJ)", file);
  return ct;
}

}  // namespace glassmap::io_detail
