// glassmap eval segments --truth FLOORPLAN --pred FLOORPLAN: segment-level floorplan scores.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli_common.hpp"
#include "glassmap/core/atomic_file.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/eval/segments.hpp"
#include "glassmap/eval/visibility.hpp"
#include "glassmap/io/floorplan.hpp"
#include "glassmap/io/log.hpp"

namespace glassmap {
namespace {

namespace fs = std::filesystem;

struct EvalSegmentsArgs {
  std::string truth, pred, json, visible_from;
  LogReadOptions read;  // of --visible-from
  eval::SegmentEvalOptions options;
  std::string units, layers;  // of the truth (layers: both)
  bool quiet = false;
};

nlohmann::json scoresJson(const eval::MaterialScores& s) {
  return {{"precision", s.precision},
          {"recall", s.recall},
          {"f1", s.f1},
          {"truth_length_m", s.truth_length},
          {"pred_length_m", s.pred_length},
          {"truth_segments", s.truth_segments},
          {"pred_segments", s.pred_segments}};
}

void run(const EvalSegmentsArgs& args) {
  const VectorMap truth = cli::readPlan(args.truth, args.units, args.layers, args.quiet, nullptr, /*clutter=*/false);
  const VectorMap pred = cli::readPlan(args.pred, "", args.layers, args.quiet, nullptr, /*clutter=*/false);
  const eval::SegmentEvalResult r = eval::evaluateSegments(truth, pred, args.options);
  // Recall against the truth the log had in line of sight; precision stays the full figure.
  eval::SegmentEvalResult seen;
  double seen_glass_f1 = 0.0, seen_wall_f1 = 0.0;
  const bool with_seen = !args.visible_from.empty();
  if (with_seen) {
    LogReadOptions read = args.read;
    read.ros2.pose_source = BagPoseSource::Auto;
    const LaserLog log = cli::readLogReporting(args.visible_from, read, args.quiet);
    const VectorMap visible = eval::visiblePart(truth, eval::viewpointsOfLog(log), args.options.sample_step);
    seen = eval::evaluateSegments(visible, pred, args.options);
    auto f1 = [](double p, double r) { return p + r > 0 ? 2 * p * r / (p + r) : 0.0; };
    seen_glass_f1 = f1(r.glass.precision, seen.glass.recall);
    seen_wall_f1 = f1(r.wall.precision, seen.wall.recall);
  }
  nlohmann::json j = {{"truth", args.truth},
                      {"pred", args.pred},
                      {"tolerance_m", r.tolerance},
                      {"glass", scoresJson(r.glass)},
                      {"wall", scoresJson(r.wall)},
                      {"glass_angle_error_deg", r.glass_angle_error_deg},
                      {"oversegmentation", r.oversegmentation},
                      {"panes_found", r.panes_found},
                      {"segments_per_found_pane", r.segments_per_found_pane},
                      {"longest_false_glass_m", r.longest_false_glass}};
  if (with_seen)
    j["seen_from_log"] = {
        {"log", args.visible_from},
        {"glass", {{"truth_length_m", seen.glass.truth_length}, {"recall", seen.glass.recall}, {"f1", seen_glass_f1}}},
        {"wall", {{"truth_length_m", seen.wall.truth_length}, {"recall", seen.wall.recall}, {"f1", seen_wall_f1}}}};
  if (!args.json.empty()) cli::writeJsonFile(args.json, j);
  if (args.quiet) return;
  std::printf("tolerance %.3f m\n", r.tolerance);
  std::printf("  %-6s %9s %9s %9s %10s %10s %6s %6s\n", "", "precision", "recall", "F1", "truth [m]", "pred [m]",
              "#truth", "#pred");
  for (const auto& [name, s] :
       {std::pair<const char*, const eval::MaterialScores&>{"glass", r.glass}, {"wall", r.wall}})
    std::printf("  %-6s %9.3f %9.3f %9.3f %10.2f %10.2f %6zu %6zu\n", name, s.precision, s.recall, s.f1, s.truth_length,
                s.pred_length, s.truth_segments, s.pred_segments);
  std::printf(
      "  glass angle error %.2f deg; over-segmentation %.2f (predicted / true panes);\n"
      "  %zu panes found, %.2f predicted segments per found pane; longest false glass %.2f m\n",
      r.glass_angle_error_deg, r.oversegmentation, r.panes_found, r.segments_per_found_pane, r.longest_false_glass);
  if (with_seen) {
    std::printf("  seen from the log (truth in line of sight of a laser pose; precision as above):\n");
    std::printf("  %-6s %9s %9s %9s %10s\n", "", "", "recall", "F1", "seen [m]");
    std::printf("  %-6s %9s %9.3f %9.3f %10.2f\n", "glass", "", seen.glass.recall, seen_glass_f1,
                seen.glass.truth_length);
    std::printf("  %-6s %9s %9.3f %9.3f %10.2f\n", "wall", "", seen.wall.recall, seen_wall_f1, seen.wall.truth_length);
  }
}

const cli::Registrar reg(74, [](CLI::App& app) {
  auto args = std::make_shared<EvalSegmentsArgs>();
  CLI::App& eval = cli::verb(app, "eval", "Score maps and trajectories against ground truth.");
  CLI::App* cmd = eval.add_subcommand(
      "segments",
      "Score a vector floorplan against the true one: length-weighted precision/recall/F1 of glass\n"
      "and walls (samples every 2 cm matched within --tol), glass angle error, over-segmentation.");
  cmd->add_option("--truth", args->truth, "true floorplan (any format glassmap reads)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--pred", args->pred, "predicted floorplan, e.g. DIR/floorplan.gpkg")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--tol", args->options.tolerance, "match distance [m]")->capture_default_str();
  cmd->add_option("--step", args->options.sample_step, "sample spacing [m]")->capture_default_str();
  cmd->add_option("--visible-from", args->visible_from,
                  "log the map was made from (CARMEN or ROS 2 bag): also score recall against only the truth\n"
                  "some laser pose had in line of sight (within range and field of view; glass is see-through)")
      ->check(CLI::ExistingPath);
  cli::addLogOptions(*cmd, args->read);
  cmd->add_option("--json", args->json, "also write the figures to this JSON file");
  cli::addUnitsOption(*cmd, args->units);
  cli::addLayersOption(*cmd, args->layers);
  cmd->add_flag("-q,--quiet", args->quiet, "print nothing (use with --json)");
  cmd->callback([args] { run(*args); });
});

}  // namespace
}  // namespace glassmap
