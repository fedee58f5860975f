// glassmap bench plan-map PLAN -o STEM: a test map of a true floorplan with furniture, in one of
// the conventions other programs leave occupancy maps in, and its truth (tools/plan_bench.py).
#include <cstdio>
#include <filesystem>

#include "cli_common.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/io/floorplan.hpp"
#include "glassmap/io/ros_map.hpp"
#include "glassmap/vector/synthetic_map.hpp"

namespace glassmap {
namespace {

namespace fs = std::filesystem;

struct PlanMapArgs {
  std::string plan, out, convention = "solid";
  bool quiet = false;
  vector::SyntheticMapOptions options;
};

void run(PlanMapArgs args) {
  args.options.convention = vector::parseMapConvention(args.convention, "--convention");
  const VectorMap plan = cli::readPlan(args.plan, "", "", args.quiet, nullptr, /*clutter=*/false);
  const vector::SyntheticMap m = vector::makeSyntheticMap(plan, args.options);
  OccupancyGridMap occ;
  occ.width = m.grid.width;
  occ.height = m.grid.height;
  occ.resolution = m.grid.resolution;
  occ.origin = Pose2(m.grid.origin.x(), m.grid.origin.y(), 0.0);
  occ.data.resize(m.grid.cells());
  for (std::size_t i = 0; i < m.grid.cells(); ++i)
    occ.data[i] = m.grid.codes[i] == kCodeEmpty ? 0 : m.grid.codes[i] == kCodeOccupied ? 100 : -1;
  fs::path stem(args.out);
  if (stem.extension() == ".yaml") stem.replace_extension();
  if (stem.has_parent_path()) fs::create_directories(stem.parent_path());
  writeRosMap(fs::path(stem.string() + ".yaml"), occ);
  writeFloorplan(fs::path(stem.string() + "-truth.geojson"), m.structure);
  if (!m.furniture.segments.empty()) writeFloorplan(fs::path(stem.string() + "-furniture.geojson"), m.furniture);
  if (args.quiet) return;
  std::printf("%-12s %d x %d cells at %.3f m, %s\n", "map", m.grid.width, m.grid.height, m.grid.resolution,
              args.convention.c_str());
  std::printf("%-12s %zu segments (structure, glass as wall)\n", "truth", m.structure.segments.size());
  std::printf("%-12s %zu pieces added, %zu outline segments in all\n", "furniture", m.pieces,
              m.furniture.segments.size());
  std::printf("%-12s %.1f m^2 free%s\n", "space", m.free_area,
              args.options.convention == vector::MapConvention::Slam
                  ? (", " + std::to_string(m.viewpoints) + " viewpoints").c_str()
                  : "");
  std::printf("%-12s %s.yaml, %s-truth.geojson\n", "wrote", stem.string().c_str(), stem.string().c_str());
}

const cli::Registrar reg(81, [](CLI::App& app) {
  CLI::App& bench = cli::verb(app, "bench", "Benchmarks that print speed and accuracy figures");
  auto args = std::make_shared<PlanMapArgs>();
  CLI::App* cmd = bench.add_subcommand(
      "plan-map",
      "A test map for the vector stage: a true floorplan rasterised with furniture of several sizes in its\n"
      "rooms, as a map editor (solid), a laser SLAM (slam: thin bands, unknown beyond) or a drawing (drawn:\n"
      "lines on white) leaves it. Writes STEM.yaml + STEM.pgm (ROS map), STEM-truth.geojson (the plan's\n"
      "structure: walls at least --structure-thickness thick and glass, all as wall) and\n"
      "STEM-furniture.geojson (the furniture's outlines).");
  cmd->add_option("plan", args->plan, "true floorplan (any OGR vector source)")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", args->out, "output stem")->required();
  cmd->add_option("--convention", args->convention, "solid | slam | drawn")
      ->check(CLI::IsMember({"solid", "slam", "drawn"}))
      ->capture_default_str();
  auto& o = args->options;
  cmd->add_option("--resolution", o.resolution, "cell size [m]")->capture_default_str();
  cmd->add_option("--furniture-cover", o.furniture_cover, "share of the floor the added furniture covers [-]")
      ->capture_default_str();
  cmd->add_flag(
      "--no-plan-furniture", [args](std::int64_t) { args->options.plan_furniture = false; },
      "leave the plan's thin outlines (the scenes' desks) out of the map");
  cmd->add_option("--bins", o.bins_per_100m2, "small obstacles (0.25-0.45 m) per 100 m^2")->capture_default_str();
  cmd->add_option("--against-wall", o.against_wall_share, "share of pieces placed against a wall [-]")
      ->capture_default_str();
  cmd->add_option("--structure-thickness", o.structure_thickness,
                  "plan walls at least this thick are structure, thinner ones furniture [m]")
      ->capture_default_str();
  cmd->add_option("--viewpoint-spacing", o.viewpoint_spacing, "slam: viewpoints on a grid this fine [m]")
      ->capture_default_str();
  cmd->add_option("--max-range", o.max_range, "slam: reach of a scan [m]")->capture_default_str();
  cmd->add_option("--range-sigma", o.range_sigma, "slam: range noise [m]")->capture_default_str();
  cmd->add_option("--seed", o.seed, "furniture, viewpoints and noise")->capture_default_str();
  cmd->add_flag("-q,--quiet", args->quiet, "print nothing");
  cmd->callback([args] { run(*args); });
});

}  // namespace
}  // namespace glassmap
