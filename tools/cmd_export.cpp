// glassmap export IN OUT: floorplan format conversion (format by extension).
#include <cctype>
#include <cstdio>
#include <filesystem>

#include "cli_common.hpp"
#include "glassmap/core/angles.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/io/floorplan.hpp"
#include "glassmap/vector/export.hpp"

namespace glassmap {
namespace {

namespace fs = std::filesystem;

struct ExportArgs {
  std::string in, out;
  std::string units, layers;
  std::string crs, origin;
  bool quiet = false;
};

void run(const ExportArgs& args) {
  const VectorMap map = cli::readPlan(args.in, args.units, args.layers, args.quiet);
  if (args.crs.empty() != args.origin.empty()) throw Error("--crs and --origin go together", {}, 0, "--crs");
  if (!args.crs.empty()) {
    FloorplanGeoref georef;
    georef.crs = args.crs;
    const Pose2 o = cli::parsePose(args.origin, "--origin");
    georef.origin = o;
    std::string ext = fs::path(args.out).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (ext == ".svg" || ext == ".png" || ext == ".pdf") {
      VectorMap placed = map;
      for (MapSegment& s : placed.segments) {
        s.a = georef.origin * s.a;
        s.b = georef.origin * s.b;
      }
      vector::exportFloorplan(args.out, placed);
    } else {
      writeFloorplan(args.out, map, georef);
    }
    if (!args.quiet)
      std::printf("in %s: map frame origin at E %.3f N %.3f, x axis %.3f deg from east\n", args.crs.c_str(),
                  georef.origin.x(), georef.origin.y(), rad2deg(georef.origin.theta));
  } else {
    vector::exportFloorplan(args.out, map);
  }
  if (!args.quiet)
    std::printf("wrote %s: %zu glass and %zu wall segments\n", args.out.c_str(), map.count(Material::Glass),
                map.count(Material::Wall));
}

const cli::Registrar reg(55, [](CLI::App& app) {
  auto args = std::make_shared<ExportArgs>();
  CLI::App* cmd = app.add_subcommand(
      "export",
      "Convert a floorplan between formats, chosen by extension: .gpkg (local metric CRS), .geojson, .shp,\n"
      ".fgb, .dxf (layers WALL and GLASS, metres), .svg, .png, .pdf (to scale, 1:100 or smaller).");
  cmd->add_option("input", args->in, "floorplan (any OGR vector source: GPKG, GeoJSON, DXF, Shapefile, FlatGeobuf)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("output", args->out, "output file")->required();
  cli::addUnitsOption(*cmd, args->units);
  cmd->add_option("--crs", args->crs,
                  "write in the building's projected CRS (EPSG:N, WKT or PROJ; metres), e.g. EPSG:25832;\n"
                  "with --origin. GPKG/SHP/FGB carry it, GeoJSON names it, DXF holds building coordinates");
  cmd->add_option("--origin", args->origin,
                  "where the map frame lies in --crs: E,N,ROT = easting and northing of the map origin [m]\n"
                  "and the map x axis' angle from east, counter-clockwise [rad]");
  cli::addLayersOption(*cmd, args->layers);
  cmd->add_flag("-q,--quiet", args->quiet, "print nothing");
  cmd->callback([args] { run(*args); });
});

}  // namespace
}  // namespace glassmap
