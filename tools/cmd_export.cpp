// glassmap export IN OUT: floorplan format conversion (format by extension).
#include <cstdio>
#include <filesystem>

#include "cli_common.hpp"
#include "glassmap/io/floorplan.hpp"
#include "glassmap/vector/export.hpp"

namespace glassmap {
namespace {

struct ExportArgs {
  std::string in, out;
  std::string units, layers;
  bool quiet = false;
};

void run(const ExportArgs& args) {
  const VectorMap map = cli::readPlan(args.in, args.units, args.layers, args.quiet);
  vector::exportFloorplan(args.out, map);
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
  cli::addLayersOption(*cmd, args->layers);
  cmd->add_flag("-q,--quiet", args->quiet, "print nothing");
  cmd->callback([args] { run(*args); });
});

}  // namespace
}  // namespace glassmap
