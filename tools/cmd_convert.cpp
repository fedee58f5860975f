// glassmap convert: floorplan from one vector format to another (format from the extension), or a
// laser log between CARMEN and ROS 2 bag.
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "cli_common.hpp"
#include "cli_georef.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/io/carmen.hpp"
#include "glassmap/io/floorplan.hpp"
#include "glassmap/io/floorplan_extras.hpp"
#include "glassmap/io/log.hpp"
#include "glassmap/io/ros2_log.hpp"

namespace glassmap {
namespace {

namespace fs = std::filesystem;

struct ConvertArgs {
  std::string in, out;
  bool quiet = false;
  std::string units, layers;
  cli::GeorefArgs georef;            // floorplans
  std::string storage, compression;  // bag output
  LogReadOptions read;               // bag input
};

bool isCarmenName(const fs::path& p) {
  std::string ext = p.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".clf" || ext == ".log" || ext == ".gz";
}

/// A CARMEN log to a bag, or a bag to a CARMEN log.
void convertLog(const ConvertArgs& args) {
  if (isRos2Bag(args.in)) {
    if (!args.storage.empty() || !args.compression.empty())
      throw Error("--storage and --compression apply to a bag written from a CARMEN log; the input is a bag", args.in);
    LogReadOptions read = args.read;
    read.ros2.pose_source = BagPoseSource::Auto;
    const LaserLog log = cli::readLogReporting(args.in, read, args.quiet);
    writeCarmenLog(args.out, log);
    if (!args.quiet)
      std::printf("read %s: %zu scans, %zu odometry records\nwrote %s (CARMEN log)\n", args.in.c_str(),
                  log.scans.size(), log.odometry.size(), args.out.c_str());
    return;
  }
  ros2::BagWriteOptions o;
  const std::string storage = args.storage.empty() ? "mcap" : args.storage;
  o.storage = storage == "sqlite3" ? ros2::BagStorage::Sqlite3 : ros2::BagStorage::Mcap;
  const std::string compression = args.compression.empty() ? (storage == "mcap" ? "zstd" : "none") : args.compression;
  if (storage == "sqlite3" && compression != "none")
    throw Error("--compression " + compression + " needs --storage mcap (sqlite3 bags are written uncompressed)");
  o.compression = compression == "zstd"  ? ros2::BagCompression::Zstd
                  : compression == "lz4" ? ros2::BagCompression::Lz4
                                         : ros2::BagCompression::None;
  CarmenReadOptions read = args.read.carmen;
  const LaserLog log = readCarmenLog(args.in, read);
  const Ros2LogWriteResult r = writeRos2Log(log, args.out, o);
  if (args.quiet) return;
  for (const std::string& n : r.notes) std::cerr << "glassmap: note: " << n << "\n";
  std::printf(
      "read %s: %zu scans, %zu odometry records\nwrote %s (ROS 2 bag, %s, %s): %zu scans, %zu odometry, "
      "%zu tf messages\n",
      args.in.c_str(), log.scans.size(), log.odometry.size(), args.out.c_str(), storage.c_str(), compression.c_str(),
      r.scans, r.odometry, r.tf_messages);
}

void run(const ConvertArgs& args) {
  if (isRos2Bag(args.in) || isCarmenName(args.in) || !args.storage.empty() || !args.compression.empty())
    return convertLog(args);
  const FloorplanFormat format = floorplanFormatFromPath(args.out);  // fail before reading
  const std::optional<FloorplanGeoref> georef = cli::georefOf(args.georef);
  VectorMap map = cli::readPlan(args.in, args.units == "0" ? "" : args.units, args.layers, args.quiet, nullptr,
                                /*clutter=*/false);
  if (map.segments.empty()) throw Error("no line segments found in floorplan", args.in);
  FloorplanExtras extras = readFloorplanExtras(args.in);
  cli::undoInputOrigin(args.georef, map, extras, args.quiet);
  writeFloorplan(args.out, map, extras, georef ? &*georef : nullptr);
  if (args.quiet) return;
  if (georef) std::printf("%s\n", cli::georefSummary(*georef).c_str());
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
                         "Convert a laser log between CARMEN and ROS 2 bag, or a floorplan between vector formats.\n"
                         "Logs: IN a ROS 2 bag (rosbag2 folder, .mcap, .db3) -> OUT a CARMEN log (.gz compressed); "
                         "IN a CARMEN log (.clf, .log, .gz) -> OUT a rosbag2 folder (created) with /scan "
                         "(LaserScan, frame laser), /odom (Odometry), /tf (odom -> base_link, and map -> odom so "
                         "that map -> laser is the log's laser pose) and /tf_static (base_link -> laser).\n"
                         "Floorplans: IN is any OGR "
                         "line source (GeoJSON, GPKG, Shapefile, FlatGeobuf, DXF, ...): material from the 'material' "
                         "field (wall/glass) or, for DXF, from the layer name (containing GLASS = glass); thickness "
                         "from the 'thickness' field [m], default 0.1; coordinates scaled to metres from the file's "
                         "units. OUT's extension picks the format: .gpkg "
                         "(local metric CRS), .geojson/.json (local metres, no CRS), .shp (+ .shx .dbf .prj .cpg), "
                         ".fgb, .dxf (layers WALL and GLASS, units metres). The output is written to a temporary "
                         "name and renamed, so a failed run leaves no partial file.");
  sub->add_option("in", args->in, "input floorplan or laser log (CARMEN or ROS 2 bag)")
      ->required()
      ->check(CLI::ExistingPath);
  sub->add_option("out", args->out, "output floorplan (format from the extension), CARMEN log or bag folder")
      ->required();
  sub->add_option("--storage", args->storage, "bag written from a CARMEN log: mcap | sqlite3 (default mcap)")
      ->check(CLI::IsMember({"mcap", "sqlite3"}));
  sub->add_option("--compression", args->compression,
                  "bag written from a CARMEN log: none | zstd | lz4 (MCAP chunks; default zstd for mcap, none "
                  "for sqlite3)")
      ->check(CLI::IsMember({"none", "zstd", "lz4"}));
  cli::addLogOptions(*sub, args->read);
  sub->add_option("--units,--unit", args->units,
                  "units of the input's coordinates, overriding what the file declares (CRS units, DXF\n"
                  "$INSUNITS; GDAL's default DXF header says inches): m, cm, mm, in, ft, us-ft, ... or metres\n"
                  "per unit (0 = the file's own); default: the file's own, metres when it declares none");
  cli::addLayersOption(*sub, args->layers);
  cli::addGeorefOptions(*sub, args->georef, /*input=*/true);
  sub->add_flag("-q,--quiet", args->quiet, "print nothing on success");
  sub->callback([args] { run(*args); });
});

}  // namespace
}  // namespace glassmap
