#pragma once
// Private to io: what the floorplan reader, writer and units code share.

#include <algorithm>
#include <cctype>
#include <string>
#include <string_view>

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

}  // namespace glassmap::io_detail
