// glassmap eval rays --plan FLOORPLAN LOG: how well a floorplan explains a log's own returns.
#include <cstdio>
#include <nlohmann/json.hpp>

#include "cli_common.hpp"
#include "glassmap/eval/consistency.hpp"
#include "glassmap/io/floorplan_extras.hpp"
#include "glassmap/io/log.hpp"

namespace glassmap {
namespace {

struct EvalRaysArgs {
  std::string plan, log, json, units, layers;
  eval::ConsistencyOptions options;
  LogReadOptions read;
  bool quiet = false, walls_only = false;
};

void run(const EvalRaysArgs& args) {
  // The plan as mapped: the building and the clutter the vectorizer kept apart from it (our
  // CLUTTER layer), or with --walls-only the building alone.
  const VectorMap plan = cli::readPlan(args.plan, args.units, args.layers, args.quiet, nullptr, !args.walls_only);
  const std::size_t clutter = args.walls_only ? 0 : readFloorplanExtras(args.plan).clutter.segments.size();
  const LaserLog log = cli::readLogReporting(args.log, args.read, args.quiet);
  const eval::ConsistencyResult r = eval::rayConsistency(log, plan, args.options);
  const nlohmann::json j = {{"plan", args.plan},
                            {"log", args.log},
                            {"tolerance_m", r.tolerance},
                            {"max_range_m", r.max_range},
                            {"scans", r.scans},
                            {"returns", r.returns},
                            {"explained", r.explained},
                            {"explained_share", r.explained_share},
                            {"explained_at_glass", r.at_glass},
                            {"short_of_plan", r.short_of_plan},
                            {"through_wall", r.through_wall},
                            {"near_segment", r.near_segment},
                            {"near_share", r.near_share},
                            {"segments", r.segments},
                            {"clutter_segments", clutter},
                            {"wall_segments", r.wall_segments},
                            {"glass_segments", r.glass_segments},
                            {"wall_length_m", r.wall_length},
                            {"glass_length_m", r.glass_length}};
  if (!args.json.empty()) cli::writeJsonFile(args.json, j);
  if (args.quiet) return;
  auto pct = [&](std::size_t k) {
    return r.returns > 0 ? 100.0 * static_cast<double>(k) / static_cast<double>(r.returns) : 0.0;
  };
  std::printf("returns under %.1f m in %zu scans: %zu\n", r.max_range, r.scans, r.returns);
  std::printf("  explained within %.3f m   %5.1f%% (%zu at glass)\n", r.tolerance, pct(r.explained), r.at_glass);
  std::printf("  short of the plan          %5.1f%% (clutter, people, or walls the plan misses)\n",
              pct(r.short_of_plan));
  std::printf("  through a wall             %5.1f%% (the plan or the pose is wrong there)\n", pct(r.through_wall));
  std::printf("end point within %.3f m of a segment %5.1f%% (whatever the beam crossed first)\n", r.tolerance,
              pct(r.near_segment));
  std::printf("plan: %zu segments (%zu wall, %.1f m; %zu glass, %.1f m)%s\n", r.segments, r.wall_segments,
              r.wall_length, r.glass_segments, r.glass_length,
              clutter > 0 ? (", " + std::to_string(clutter) + " of the walls from the clutter layer").c_str() : "");
}

const cli::Registrar reg(75, [](CLI::App& app) {
  auto args = std::make_shared<EvalRaysArgs>();
  CLI::App& eval = cli::verb(app, "eval", "Score maps and trajectories against ground truth.");
  CLI::App* cmd = eval.add_subcommand(
      "rays",
      "Score a floorplan against a log without ground truth: the share of the log's returns whose\n"
      "range the plan predicts within --tol (beams cross glass; a reading at a pane or behind it\n"
      "counts), the rest split into readings short of the plan (clutter, people, missing walls) and\n"
      "readings through a wall, and the plan's size (segments, metres). Laser poses are taken as\n"
      "given: use the log the plan was made from, or one with corrected poses.");
  cmd->add_option("--plan", args->plan, "floorplan (any format glassmap reads), e.g. DIR/floorplan.gpkg")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("log", args->log, "laser log (CARMEN or ROS 2 bag) whose laser poses are in the plan's frame")
      ->required();
  cmd->add_option("--tol", args->options.tolerance, "a return is explained within this distance of a surface [m]")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--max-range", args->options.max_range, "score returns up to this range [m]")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--max-scans", args->options.max_scans, "score this many scans spread over the log (0: all)")
      ->capture_default_str();
  cmd->add_flag("--walls-only", args->walls_only,
                "score the building alone: leave the plan's CLUTTER layer (furniture kept apart from the\n"
                "walls, read as walls by default) out");
  cmd->add_option("--json", args->json, "also write the figures to this JSON file");
  cli::addLogOptions(*cmd, args->read);
  cli::addUnitsOption(*cmd, args->units);
  cli::addLayersOption(*cmd, args->layers);
  cmd->add_flag("-q,--quiet", args->quiet, "print nothing (use with --json)");
  cmd->callback([args] { run(*args); });
});

}  // namespace
}  // namespace glassmap
