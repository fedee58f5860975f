#pragma once
/// Georeferencing options shared by the verbs that write floorplans (map, vectorize, export,
/// convert): --crs EPSG:N --origin E,N,ROT writes in the building's projected CRS; --input-origin
/// says where a plan read in building coordinates (DXF, Shapefile, ...) has its map frame, to undo
/// it. The rotation always carries its unit (30deg, 0.5236rad): a bare number is ambiguous.

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

#include "glassmap/core/pose2.hpp"
#include "glassmap/io/floorplan_extras.hpp"

namespace glassmap::cli {

/// The options as given on the command line.
struct GeorefArgs {
  std::string crs;           ///< --crs: EPSG:N, WKT or PROJ (projected, metres)
  std::string origin;        ///< --origin: E,N,ROT of the map frame in --crs
  std::string input_origin;  ///< --input-origin: E,N,ROT of the input plan's map frame
};

/// Adds --crs and --origin (and, with `input`, --input-origin) to a verb.
void addGeorefOptions(CLI::App& cmd, GeorefArgs& args, bool input = false);

/// "E,N,ROT" [m, m, rad] with ROT as "<number>deg", "<number>°" or "<number>rad" (0 alone is
/// allowed); throws Error naming `field` for anything else.
Pose2 parseOrigin(const std::string& text, const std::string& field);

/// The georeference to write with; none when neither --crs nor --origin is given. Throws Error
/// when only one of them is.
std::optional<FloorplanGeoref> georefOf(const GeorefArgs& args);

/// Moves a plan (and its extra layers) read in building coordinates back into its map frame when
/// --input-origin is given; says so unless `quiet`.
void undoInputOrigin(const GeorefArgs& args, VectorMap& map, FloorplanExtras& extras, bool quiet);

/// One line for the summary: "in EPSG:25832: map frame origin at E 500000.000 N ..., x axis 30.000 deg from east".
std::string georefSummary(const FloorplanGeoref& g);

}  // namespace glassmap::cli
