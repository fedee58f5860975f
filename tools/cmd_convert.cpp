// glassmap convert: floorplan from one vector format to another (format from the extension).
#include <cstdio>
#include <memory>
#include <string>

#include "cli_common.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/io/floorplan.hpp"

namespace glassmap {
namespace {

struct ConvertArgs {
  std::string in, out;
  bool quiet = false;
  std::string units, layers;
};

void run(const ConvertArgs& args) {
  const FloorplanFormat format = floorplanFormatFromPath(args.out);  // fail before reading
  const VectorMap map = cli::readPlan(args.in, args.units == "0" ? "" : args.units, args.layers, args.quiet);
  if (map.segments.empty()) throw Error("no line segments found in floorplan", args.in);
  writeFloorplan(args.out, map);
  if (args.quiet) return;
  const Eigen::AlignedBox2d b = map.bounds();
  std::printf("read %s: %zu segments (%zu wall, %zu glass), x %.3f .. %.3f m, y %.3f .. %.3f m\n", args.in.c_str(),
              map.segments.size(), map.count(Material::Wall), map.count(Material::Glass), b.min().x(), b.max().x(),
              b.min().y(), b.max().y());
  std::printf("wrote %s (%s)\n", args.out.c_str(), std::string(gdalDriverName(format)).c_str());
}

const cli::Registrar reg(20, [](CLI::App& app) {
  auto args = std::make_shared<ConvertArgs>();
  CLI::App* sub =
      app.add_subcommand("convert",
                         "Convert a floorplan of wall and glass line segments between vector formats. IN is any OGR "
                         "line source (GeoJSON, GPKG, Shapefile, FlatGeobuf, DXF, ...): material from the 'material' "
                         "field (wall/glass) or, for DXF, from the layer name (containing GLASS = glass); thickness "
                         "from the 'thickness' field [m], default 0.1; coordinates scaled to metres from the file's "
                         "units. OUT's extension picks the format: .gpkg "
                         "(local metric CRS), .geojson/.json (local metres, no CRS), .shp (+ .shx .dbf .prj .cpg), "
                         ".fgb, .dxf (layers WALL and GLASS, units metres). The output is written to a temporary "
                         "name and renamed, so a failed run leaves no partial file.");
  sub->add_option("in", args->in, "input floorplan")->required()->check(CLI::ExistingFile);
  sub->add_option("out", args->out, "output floorplan; format from the extension")->required();
  sub->add_option("--units,--unit", args->units,
                  "units of the input's coordinates, overriding what the file declares (CRS units, DXF\n"
                  "$INSUNITS; GDAL's default DXF header says inches): m, cm, mm, in, ft, us-ft, ... or metres\n"
                  "per unit (0 = the file's own); default: the file's own, metres when it declares none");
  cli::addLayersOption(*sub, args->layers);
  sub->add_flag("-q,--quiet", args->quiet, "print nothing on success");
  sub->callback([args] { run(*args); });
});

}  // namespace
}  // namespace glassmap
