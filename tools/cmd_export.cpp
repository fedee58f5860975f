// glassmap export IN OUT: floorplan format conversion (format by extension), with the extra
// layers (clutter, doors, rooms) and optionally in the building's projected CRS.
#include <cstdio>
#include <filesystem>

#include "cli_common.hpp"
#include "cli_georef.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/io/floorplan.hpp"
#include "glassmap/io/floorplan_extras.hpp"
#include "glassmap/vector/export.hpp"

namespace glassmap {
namespace {

struct ExportArgs {
  std::string in, out;
  std::string units, layers;
  cli::GeorefArgs georef;
  bool quiet = false;
};

void run(const ExportArgs& args) {
  const std::optional<FloorplanGeoref> georef = cli::georefOf(args.georef);  // fail before reading
  if (!vector::isExportFormat(args.out))
    throw Error("unknown floorplan format (expected .gpkg, .geojson, .json, .shp, .fgb, .dxf, .svg, .png or .pdf)",
                args.out);
  VectorMap map = cli::readPlan(args.in, args.units, args.layers, args.quiet, nullptr, /*clutter=*/false);
  FloorplanExtras extras = readFloorplanExtras(args.in);
  cli::undoInputOrigin(args.georef, map, extras, args.quiet);
  vector::exportFloorplan(args.out, map, extras, georef ? &*georef : nullptr);
  if (args.quiet) return;
  if (georef) std::printf("%s\n", cli::georefSummary(*georef).c_str());
  std::printf("wrote %s: %zu glass and %zu wall segments", args.out.c_str(), map.count(Material::Glass),
              map.count(Material::Wall));
  if (!extras.empty())
    std::printf("; %zu clutter segments, %zu doors, %zu rooms", extras.clutter.segments.size(), extras.doors.size(),
                extras.rooms.size());
  std::printf("\n");
}

const cli::Registrar reg(55, [](CLI::App& app) {
  auto args = std::make_shared<ExportArgs>();
  CLI::App* cmd = app.add_subcommand(
      "export",
      "Convert a floorplan between formats, chosen by extension: .gpkg (local metric CRS), .geojson, .shp,\n"
      ".fgb, .dxf (layers WALL and GLASS, metres), .svg, .png, .pdf (to scale, 1:100 or smaller). The extra\n"
      "layers of a glassmap plan (CLUTTER, DOOR, ROOMS) go into .gpkg, .geojson and .dxf.");
  cmd->add_option("input", args->in, "floorplan (any OGR vector source: GPKG, GeoJSON, DXF, Shapefile, FlatGeobuf)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("output", args->out, "output file")->required();
  cli::addUnitsOption(*cmd, args->units);
  cli::addGeorefOptions(*cmd, args->georef, /*input=*/true);
  cli::addLayersOption(*cmd, args->layers);
  cmd->add_flag("-q,--quiet", args->quiet, "print nothing");
  cmd->callback([args] { run(*args); });
});

}  // namespace
}  // namespace glassmap
