// glassmap vectorize DIR/labels.tif -o OUT: label raster -> wall and glass floorplan.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "cli_common.hpp"
#include "cli_georef.hpp"
#include "glassmap/core/angles.hpp"
#include "glassmap/core/atomic_file.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/io/labels_raster.hpp"
#include "glassmap/io/log.hpp"
#include "glassmap/io/ros_map.hpp"
#include "glassmap/pipeline/reports.hpp"
#include "glassmap/vector/export.hpp"
#include "glassmap/vector/from_occupancy.hpp"
#include "glassmap/vector/scan_fit.hpp"
#include "glassmap/vector/vectorize.hpp"

namespace glassmap {
namespace {

namespace fs = std::filesystem;

struct VectorizeArgs {
  std::string labels, out, formats = "gpkg,geojson,dxf,svg,png", json;
  std::string input = "auto";
  std::string log;  // --log: the walls moved onto its returns
  LogReadOptions read;
  double occupied_thresh = 0.65, free_thresh = 0.196;
  vector::OccupancyOptions occupancy;
  bool no_regularize = false, quiet = false;
  cli::GeorefArgs georef;
  vector::VectorizeOptions options;
  vector::ScanClutterOptions scan_clutter;  // with --log
};

// The input as a label grid, and where its lower-left corner lies (with the yaw of a ROS map).
struct Input {
  vector::LabelGrid grid;
  Pose2 origin;         // applied to the fitted segments (grid.origin is then zero)
  std::string read_as;  // "labels", "ROS occupancy map", "occupancy image"
  vector::OccupancyStats occupancy;
};

Input readInput(const VectorizeArgs& a) {
  Input in;
  const std::string ext = fs::path(a.labels).extension().string();
  const bool yaml = ext == ".yaml" || ext == ".yml";
  if (yaml && a.input == "labels") throw Error("a map YAML is an occupancy map, not labels", a.labels, 0, "--input");
  if (yaml) {
    const OccupancyGridMap map = readRosMap(a.labels);
    in.grid = vector::fromOccupancy(map, a.occupancy, &in.occupancy);
    in.origin = map.origin;
    in.read_as = "ROS occupancy map";
    return in;
  }
  const LabelRaster raster = readLabelRaster(a.labels);
  const bool labels = a.input == "labels" || (a.input == "auto" && vector::looksLikeLabelCodes(raster));
  if (labels) {
    in.grid = vector::toLabelGrid(raster);
    in.read_as = "labels";
    return in;
  }
  in.grid = vector::fromOccupancyRaster(raster, a.occupied_thresh, a.free_thresh, a.occupancy, &in.occupancy);
  in.read_as = "occupancy image";
  if (a.input == "auto" && !a.quiet)
    std::cerr << "glassmap: " << a.labels
              << ": values outside the label codes: read as an occupancy image (dark = occupied, "
                 "occupancy = (255 - v) / 255 above "
              << a.occupied_thresh << ", free below " << a.free_thresh << "; --input labels to override)\n";
  return in;
}

// OUT: an existing directory or one ending in '/' -> DIR/floorplan; "name.<format>" -> "name"; else the stem itself.
fs::path outputStem(const std::string& out) {
  const fs::path p(out);
  if (!out.empty() && (out.back() == '/' || fs::is_directory(p))) return p / "floorplan";
  if (vector::isExportFormat(p)) return fs::path(p).replace_extension();
  return p;
}

std::vector<std::string> splitFormats(const std::string& list) {
  std::vector<std::string> out;
  std::stringstream ss(list);
  for (std::string f; std::getline(ss, f, ',');) {
    if (f.empty()) continue;
    if (!vector::isExportFormat("x." + f)) throw Error("unknown format '" + f + "'", {}, 0, "--formats");
    out.push_back(f);
  }
  if (out.empty()) throw Error("no output format given", {}, 0, "--formats");
  return out;
}

void run(const VectorizeArgs& args) {
  const std::vector<std::string> formats = splitFormats(args.formats);
  const std::optional<FloorplanGeoref> georef = cli::georefOf(args.georef);
  const Input input = readInput(args);
  const vector::LabelGrid& grid = input.grid;
  // Read before anything is written: a bad log leaves no output behind.
  std::optional<LaserLog> log;
  if (!args.log.empty()) log = cli::readLogReporting(args.log, args.read, args.quiet);
  vector::VectorizeOptions options = args.options;
  options.regularize = !args.no_regularize;
  vector::VectorizeResult r = vector::vectorize(grid, options);
  r.map = vector::placeOnPose(std::move(r.map), input.origin);
  r.map.name = fs::path(args.labels).parent_path().filename().string();
  const fs::path stem = outputStem(args.out);
  if (stem.has_parent_path()) fs::create_directories(stem.parent_path());
  r.extras.clutter = vector::placeOnPose(std::move(r.extras.clutter), input.origin);
  for (DoorOpening& d : r.extras.doors) d.a = input.origin * d.a, d.b = input.origin * d.b;
  for (RoomPolygon& room : r.extras.rooms)
    for (Vec2& p : room.ring) p = input.origin * p;
  // With the log the map was made from: the walls where its returns put them (as `map` does).
  vector::ScanFitStats fit;
  vector::ScanClutterStats clutter;
  if (log) {
    fit = vector::fitToScans(r, *log, grid::BeamOptions{});
    if (fit.returns == 0)
      std::cerr << "glassmap: warning: " << args.log
                << ": no return lies within 0.2 m of a wall: are the log's poses in the map's frame?\n";
    // The clutter layer from the returns the walls leave (as `map` does).
    if (args.scan_clutter.enabled)
      clutter = vector::clutterFromScans(r, *log, grid::BeamOptions{}, &grid, input.origin, args.scan_clutter);
  }
  const auto written = vector::writeFloorplanSet(stem, r.map, formats, r.extras, georef ? &*georef : nullptr);

  const auto& s = r.stats;
  const vector::OccupancyStats& o = input.occupancy;
  const nlohmann::json j = {{"labels", args.labels},
                            {"read_as", input.read_as},
                            {"occupancy",
                             {{"free", o.free},
                              {"occupied", o.occupied},
                              {"unknown", o.unknown},
                              {"solid_inside", o.solid_inside},
                              {"ridges", o.ridges}}},
                            {"glass_segments", r.map.count(Material::Glass)},
                            {"wall_segments", r.map.count(Material::Wall)},
                            {"glass_cells", s.glass_cells},
                            {"wall_cells", s.wall_cells},
                            {"regions", s.regions},
                            {"bic_splits", s.bic_splits},
                            {"merges", s.merges},
                            {"face_merges", s.face_merges},
                            {"wall_thickness", s.wall_thickness},
                            {"regularized", s.regularized},
                            {"corners", s.corners},
                            {"dropped", s.dropped},
                            {"glass_continued", s.continued},
                            {"dominant_axis_deg", s.dominant_axis_deg},
                            {"directions_deg", s.directions_deg},
                            {"lines", s.lines},
                            {"bridged", s.bridged},
                            {"openings", s.openings},
                            {"clutter_segments", r.extras.clutter.segments.size()},
                            {"doors", r.extras.doors.size()},
                            {"rooms", r.extras.rooms.size()},
                            {"scan_fit", pipeline::scanFitJson(fit)},
                            {"scan_fit_log", args.log},
                            {"scan_clutter", pipeline::scanClutterJson(clutter)},
                            {"seconds", s.seconds}};
  if (!args.json.empty()) cli::writeJsonFile(args.json, j);
  if (args.quiet) return;
  std::printf("%-22s %zu x %zu cells at %.3f m (%s)\n", "input", static_cast<std::size_t>(grid.width),
              static_cast<std::size_t>(grid.height), grid.resolution, input.read_as.c_str());
  if (input.read_as != "labels")
    std::printf(
        "%-22s %zu free, %zu occupied (%zu of them thin walls read by their ridge; %zu inside solid areas, "
        "dropped: only faces of free space are walls), %zu unknown\n",
        "occupancy", o.free, o.occupied, o.ridges, o.solid_inside, o.unknown);
  std::printf("%-22s %zu glass, %zu wall\n", "cells", s.glass_cells, s.wall_cells);
  std::printf("%-22s %zu glass, %zu wall\n", "segments", r.map.count(Material::Glass), r.map.count(Material::Wall));
  std::printf("%-22s %zu regions, %zu BIC splits, %zu merges, %zu wall faces merged, %zu dropped\n", "fitting",
              s.regions, s.bic_splits, s.merges, s.face_merges, s.dropped);
  if (s.wall_thickness > args.options.max_wall_thickness)
    std::printf(
        "%-22s faces up to %.2f m apart are one wall: the building's long walls seen from both sides are "
        "that thick (measured; --max-wall-thickness %.2f)\n",
        "wall thickness", s.wall_thickness, args.options.max_wall_thickness);
  std::printf("%-22s %.1f deg, %zu segments snapped, %zu ends joined\n", "axes", s.dominant_axis_deg, s.regularized,
              s.corners);
  std::printf("%-22s %zu lines, %zu gaps bridged, %zu openings, %zu doors, %zu rooms, %zu clutter segments\n",
              "structure", s.lines, s.bridged, s.openings, r.extras.doors.size(), r.extras.rooms.size(),
              r.extras.clutter.segments.size());
  if (!args.log.empty()) std::printf("%-22s %s\n", "walls onto returns", cli::scanFitSummary(fit).c_str());
  if (!args.log.empty() && args.scan_clutter.enabled)
    std::printf("%-22s %s\n", "clutter from returns", cli::scanClutterSummary(clutter).c_str());
  if (georef) std::printf("%-22s %s\n", "georeference", cli::georefSummary(*georef).c_str());
  std::printf("%-22s %.3f s\n", "time", s.seconds);
  for (const auto& p : written) std::printf("%-22s %s\n", "wrote", p.string().c_str());
}

void addMaterialOptions(CLI::App* cmd, const std::string& prefix, vector::MaterialOptions& o) {
  cmd->add_option("--" + prefix + "-merge-gap", o.merge_gap,
                  prefix + ": merge collinear pieces across gaps up to this [m]")
      ->capture_default_str();
  cmd->add_option("--" + prefix + "-min-length", o.min_length, prefix + ": drop shorter segments [m]")
      ->capture_default_str();
  const bool wall = prefix == "wall";
  cmd->add_option("--" + prefix + "-radius", o.neighbour_radius,
                  prefix + ": region growing neighbour radius [m]" + (wall ? " (at least 1.6 cells)" : ""))
      ->capture_default_str();
  cmd->add_option("--" + prefix + "-max-distance", o.max_distance,
                  prefix + ": region growing band half-width [m]" + (wall ? " (at least 1.5 cells)" : ""))
      ->capture_default_str();
}

const cli::Registrar reg(50, [](CLI::App& app) {
  auto args = std::make_shared<VectorizeArgs>();
  CLI::App* cmd = app.add_subcommand(
      "vectorize",
      "Fit wall and glass line segments to a label GeoTIFF (DIR/labels.tif of 'glassmap map'), a ROS/nav2\n"
      "occupancy map (map.yaml + PGM/PNG from slam_toolbox, cartographer, gmapping, map editors; mode,\n"
      "negate, thresholds and origin yaw honoured) or any single-band occupancy image GDAL reads with a\n"
      "geotransform (GeoTIFF, PNG + world file). In an occupancy map only the faces of free space are walls:\n"
      "the inside of a solid occupied area (a building's outside drawn black, a filled pillar) is dropped.\n"
      "OUT is a stem: writes OUT.gpkg, OUT.geojson, OUT.dxf, OUT.svg, OUT.png (see --formats);\n"
      "an existing directory or a path ending in '/' writes DIR/floorplan.*; 'plan.gpkg' means the stem 'plan'.");
  cmd->add_option("labels", args->labels,
                  "label GeoTIFF (codes 0 unknown, 1 empty, 2 occupied, 10+k glass), map YAML, or occupancy raster")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--input", args->input,
                  "what the raster holds: auto (a .yaml is a ROS map; a raster whose values are all label\n"
                  "codes is labels, any other an occupancy image, said on stderr) | labels | occupancy")
      ->check(CLI::IsMember({"auto", "labels", "occupancy"}))
      ->capture_default_str();
  cmd->add_option("--occupied-thresh", args->occupied_thresh,
                  "occupancy image: (255 - v) / 255 above this is occupied (a map YAML has its own)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--free-thresh", args->free_thresh, "occupancy image: below this is free")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--face-cells", args->occupancy.face_cells,
                  "occupancy maps: occupied cells farther than this from free space are a solid area's\n"
                  "inside and dropped [cells]; -1 keeps every occupied cell")
      ->capture_default_str();
  cmd->add_option("--rim-cells", args->occupancy.rim_cells,
                  "occupancy maps: free space reaches through this many unknown cells first (the grey rim\n"
                  "anti-aliasing or resampling leaves along drawn walls) [cells]; 0: none")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag(
      "--no-ridges", [args](std::int64_t) { args->occupancy.ridges = false; },
      "occupancy maps: thresholds only (by default a cell read as unknown that is darker than the cells\n"
      "either side of it across a row, column or diagonal, and darker than a quarter of the way from\n"
      "free_thresh to occupied_thresh, is occupied: a thin wall a blur or a resampling made grey)");
  cmd->add_option("-o,--output", args->out, "output stem or directory")->required();
  cmd->add_option("--formats", args->formats, "comma-separated: gpkg,geojson,json,shp,fgb,dxf,svg,png,pdf")
      ->capture_default_str();
  cmd->add_flag("--no-regularize", args->no_regularize, "keep fitted directions (no snapping to the dominant axes)");
  cmd->add_flag(
      "--no-structure", [args](std::int64_t) { args->options.structure.enabled = false; },
      "plain fit: every face of free space is a wall (no clutter layer, no bridging, no doors)");
  cmd->add_option("--corner-snap", args->options.corner_snap, "join wall ends this close to another wall [m] (0: off)")
      ->capture_default_str();
  cmd->add_option("--glass-corner-snap", args->options.glass_corner_snap,
                  "a pane's end moves onto a wall this far away (a pane ends in a frame), unless its line runs on "
                  "as a wall there [m] (at least --corner-snap)")
      ->capture_default_str();
  cmd->add_option("--max-wall-thickness", args->options.max_wall_thickness,
                  "merge parallel wall faces closer than this into one centre line [m]; a building whose long walls "
                  "seen from both sides are thicker (6 m of them or more within a cell and a half of one thickness) "
                  "has its own thickness measured and used instead, at most --max-two-sided-thickness (printed, "
                  "and wall_thickness in --json)")
      ->capture_default_str();
  cmd->add_option("--max-two-sided-thickness", args->options.max_two_sided_thickness,
                  "also merge faces up to this far apart when free space lies outside both (within 0.7 m: "
                  "furniture may stand against a face) and they overlap over 3 m or more, also once the structure "
                  "step has joined a face's pieces (a thick wall seen from both sides; a shorter pair is furniture "
                  "against a wall, unless the building's own wall thickness, measured, covers it) [m] (at most "
                  "--max-wall-thickness: off)")
      ->capture_default_str();
  cmd->add_option("--noise-floor", args->options.noise_floor,
                  "BIC: floor of the rms cell offset from a line [cells]; higher merges more")
      ->capture_default_str();
  addMaterialOptions(cmd, "glass", args->options.glass);
  addMaterialOptions(cmd, "wall", args->options.wall);
  cmd->add_option("--line-tolerance", args->options.structure.line_tolerance,
                  "structure: pieces of one direction whose offsets differ by less share a wall line [m]")
      ->capture_default_str();
  cmd->add_option("--min-line-support", args->options.structure.min_line_support,
                  "structure: a wall line whose pieces sum to less is clutter unless it joins walls [m]")
      ->capture_default_str();
  cmd->add_option("--log", args->log,
                  "the laser log the map was made from (CARMEN or ROS 2 bag, its poses in the map's frame): each\n"
                  "wall and clutter segment then moves along its normal onto the densest 0.1 m wide band of the\n"
                  "log's returns nearest to it, as `map` does (corners, T junctions and doors follow)")
      ->check(CLI::ExistingPath);
  cmd->add_flag("!--no-scan-clutter", args->scan_clutter.enabled,
                "with --log: keep the clutter layer the cells draw; by default it is replaced by segments chosen\n"
                "to explain the log's returns under 8 m that the walls leave, never fewer than the cells' pieces\n"
                "explained (as `map` does)");
  cmd->add_option("--clutter-min-share", args->scan_clutter.min_share,
                  "with --log: the share of the log's returns under 8 m a clutter segment must explain")
      ->capture_default_str()
      ->check(CLI::Range(1e-6, 1.0));
  cli::addLogOptions(*cmd, args->read);
  cli::addGeorefOptions(*cmd, args->georef);
  cmd->add_option("--json", args->json, "also write the figures to this JSON file");
  cmd->add_flag("-q,--quiet", args->quiet, "print nothing");
  cmd->callback([args] { run(*args); });
});

}  // namespace
}  // namespace glassmap
