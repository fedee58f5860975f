#pragma once
// Private to io: what the floorplan reader, writer and units code share.

#include <algorithm>
#include <cctype>
#include <optional>
#include <string>
#include <string_view>

#include "glassmap/core/pose2.hpp"

#include <filesystem>
#include <memory>

class GDALDataset;
class OGRCoordinateTransformation;
class OGRSpatialReference;
class OGRFeature;
class OGRLayer;

namespace glassmap::io_detail {

inline constexpr const char* kFloorplanLayerName = "floorplan";  ///< layer name of our outputs
/// The marker glassmap writes into its GeoJSON (the collection's "description"): local metres.
inline constexpr const char* kGeoJsonMarker = "glassmap floorplan: local metres";
/// WKT of the local engineering CRS of our GPKG, Shapefile and FlatGeobuf outputs.
inline constexpr std::string_view kLocalWkt =
    R"wkt(LOCAL_CS["glassmap local frame (metres)",LOCAL_DATUM["glassmap floor",0],UNIT["metre",1,AUTHORITY["EPSG","9001"]],AXIS["X",EAST],AXIS["Y",NORTH]])wkt";

/// Lower-case ASCII copy.
inline std::string lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

/// "inches", "metres", ... for a unit of that many metres, else "<x> m per unit".
std::string unitName(double metres);

/// Layer metadata of a georeferenced GPKG: "E N ROT_RAD", the map frame's origin in its CRS.
inline constexpr const char* kMapFrameOriginKey = "GLASSMAP_MAP_FRAME_ORIGIN";
/// A georeferenced GeoJSON of ours: its "description" is this prefix and "E N ROT_RAD".
inline constexpr const char* kGeoJsonOriginPrefix = "glassmap floorplan: map frame origin ";

/// Which extra layer of ours a feature belongs to (floorplan_extras.hpp).
enum class ExtraLayer { None, Clutter, Door, Room };

/// The extra layer of a feature: by OGR layer name in a GPKG of ours (`ours`: the dataset has our
/// floorplan layer), by its `layer` member (GeoJSON), or by its CAD layer (DXF).
ExtraLayer extraLayerOf(bool ours, const char* ogr_layer, OGRFeature& f, const std::string& cad_layer);

/// The map frame's origin recorded in a layer's metadata (kMapFrameOriginKey), if any; throws
/// Error naming the file and key when it is malformed.
std::optional<Pose2> mapFrameOrigin(OGRLayer& layer, const std::string& file);

/// What the text of a GeoJSON file says before its features: an old-style "crs" member, and
/// glassmap's marker (floorplan_geo.cpp).
struct GeoJsonHead {
  bool has_crs = false;
  bool glassmap = false;
};
GeoJsonHead geoJsonHead(const std::filesystem::path& path);

/// A transformation from a geographic CRS to metres of a transverse Mercator centred on (lon, lat):
/// a local metric frame in which a building's plan keeps its shape to well under a millimetre.
std::unique_ptr<OGRCoordinateTransformation> toLocalMetres(const OGRSpatialReference& geographic, double lon,
                                                           double lat, const std::string& file);

/// True when the dataset has our floorplan layer.
bool hasFloorplanLayer(GDALDataset& ds);

}  // namespace glassmap::io_detail
