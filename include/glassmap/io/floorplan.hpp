#pragma once
/// Floorplans (wall and glass line segments) in the formats GIS and CAD tools read, through GDAL/OGR.
///
/// Attributes per line: material (wall|glass), thickness [m], pane_angle [rad], support, evidence.
/// Coordinates are local metres on one floor. GeoJSON cannot carry a local CRS (GDAL drops it):
/// a GeoJSON floorplan is read and written as local metres. DXF carries the material in the layer
/// (WALL, GLASS) and the other attributes in the entity's XDATA (application GLASSMAP).

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "glassmap/core/pose2.hpp"
#include "glassmap/geometry/vector_map.hpp"
#include "glassmap/io/floorplan_layers.hpp"

namespace glassmap {

/// Output formats of writeFloorplan.
enum class FloorplanFormat { Gpkg, GeoJson, Shapefile, FlatGeobuf, Dxf };

/// Format from the extension: .gpkg, .geojson/.json, .shp, .fgb, .dxf (case-insensitive);
/// throws Error for any other.
FloorplanFormat floorplanFormatFromPath(const std::filesystem::path& path);

/// GDAL driver name of a format ("GPKG", "GeoJSON", "ESRI Shapefile", "FlatGeobuf", "DXF").
std::string_view gdalDriverName(FloorplanFormat format);

/// What readFloorplan assumed about units (for the caller to report).
struct FloorplanUnits {
  double unit_in_metres = 1.0;  ///< metres per file unit used for the first layer
  std::string source;           ///< where it came from: "option", "DXF $INSUNITS 1 (inches)", "CRS
                                ///< linear unit (US survey foot)", "none declared: metres"
};

/// Options of readFloorplan.
struct FloorplanReadOptions {
  double unit_in_metres = 0.0;            ///< metres per file unit; 0: from the file (CRS linear units, DXF
                                          ///< $INSUNITS; metres when the file declares none)
  FloorplanUnits* units = nullptr;        ///< if set, receives what was assumed
  std::vector<LayerRule> layer_rules;     ///< user rules, tried before the built-in layer table
  FloorplanReadReport* report = nullptr;  ///< if set, receives what was read as what
  bool clutter = true;                    ///< read a CLUTTER layer of ours as walls (every surface a laser
                                          ///< sees: localize, calibrate); false: the building only (eval
                                          ///< segments, export); DOOR and ROOMS layers are never surfaces
  bool building_frame = false;            ///< keep a georeferenced GPKG in its CRS instead of moving it back
                                          ///< into the map frame it records
};

/// Metres per unit of a unit name: m, dm, cm, mm, km, in, ft, us-ft, yd; or a positive number
/// (metres per unit). Throws Error naming `field` otherwise.
double parseLengthUnit(const std::string& text, const std::string& field = "units");

/// A warning when a plan's extent is implausible for a building floor (larger side under 2 m or
/// over 5 km), naming the units assumed and what to pass instead; empty when plausible. The
/// extent is that of the bulk of the drawing (1st to 99th percentile by segment length), so a
/// stray segment far away does not count.
std::string implausibleExtentWarning(const VectorMap& map, const FloorplanUnits& units,
                                     const std::filesystem::path& path);

/// Reads every line of any OGR vector source: LineString, MultiLineString and polygon rings;
/// our extra layers (floorplan_extras.hpp: clutter, doors, rooms) are skipped, and a GPKG that
/// records its map frame's origin (writeFloorplan with a FloorplanGeoref) is read back in that
/// map frame (unless options.building_frame), said in the report's notes;
/// a polyline becomes its consecutive segments. Material from the `material` field (or DXF XDATA),
/// else from the CAD layer (`Layer` field): options.layer_rules, then standardLayerRules() (wall,
/// glass, or ignored: annotation, doors, furniture, ...), unknown names as wall; else from the OGR
/// layer name (user rules, the table's glass names, else wall). DXF: blocks are exploded with
/// AutoCAD's layer inheritance (entities on layer 0 take the INSERT's layer); paper space, frozen
/// and off layers, dimensions, leaders, hatches and text are ignored; splines given by fit points
/// only are read as polylines through them. Throws Error when every line was ignored.
/// Thickness from the `thickness` field (or DXF XDATA), default 0.1 m. Coordinates in a CRS with
/// other linear units, or a DXF declaring other units ($INSUNITS: mm, cm, inches, ...), are scaled
/// to metres (note: GDAL's own default DXF header declares inches); geographic (degree)
/// coordinates are an Error.
VectorMap readFloorplan(const std::filesystem::path& path, const FloorplanReadOptions& options = {});

/// Writes one line feature per segment in the format of the extension, atomically: GPKG with a
/// local engineering CRS in metres, GeoJSON (no CRS: local metres), ESRI Shapefile (.shp, .shx,
/// .dbf, .prj, .cpg written in a temporary folder, then moved into place), FlatGeobuf (no spatial
/// index, so features keep their order), DXF (layers WALL and GLASS in distinct colours, header
/// $INSUNITS 6 = metres and $MEASUREMENT 1 = metric).
void writeFloorplan(const std::filesystem::path& path, const VectorMap& map);

/// Where the robot's map frame lies in a building's projected CRS: a point p of the map frame is
/// origin * p there (easting, northing in metres; rotation of the map frame's x axis from east,
/// counter-clockwise).
struct FloorplanGeoref {
  std::string crs;  ///< "EPSG:25832", a WKT or PROJ string: a projected CRS in metres
  Pose2 origin;     ///< [m, m, rad]
};

/// writeFloorplan in the building's CRS: coordinates moved by georef.origin; GPKG, Shapefile and
/// FlatGeobuf carry the CRS, GeoJSON names it in its "crs" member (not RFC 7946's lon/lat), DXF
/// holds the building coordinates (DXF has no CRS). GPKG also records the origin (layer metadata
/// GLASSMAP_MAP_FRAME_ORIGIN = "E N ROT_RAD") so the robot frame can be recovered. Throws Error
/// for an unknown, geographic or non-metre CRS, naming it.
void writeFloorplan(const std::filesystem::path& path, const VectorMap& map, const FloorplanGeoref& georef);

/// WKT of the local engineering CRS written into GPKG, Shapefile and FlatGeobuf outputs.
std::string_view localMetricCrsWkt();

}  // namespace glassmap
