// glassmap eval cells --truth FLOORPLAN --labels DIR/labels.tif: Table I of a glass map.
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli_common.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/core/labels.hpp"
#include "glassmap/eval/cells.hpp"
#include "glassmap/io/floorplan.hpp"
#include "glassmap/io/labels_raster.hpp"

namespace glassmap {
namespace {

namespace fs = std::filesystem;

struct EvalCellsArgs {
  std::string truth;
  std::string labels;
  std::string json;
  eval::CellEvalOptions options;
  std::string units, layers;  // of the truth
  bool quiet = false;
};

nlohmann::json scoresJson(const eval::DetectionScores& s) {
  return {{"precision", s.precision}, {"recall", s.recall}, {"f1", s.f1}};
}

void run(const EvalCellsArgs& args) {
  const VectorMap truth = cli::readPlan(args.truth, args.units, args.layers, args.quiet, nullptr, /*clutter=*/false);
  const LabelRaster raster = readLabelRaster(args.labels);
  grid::GridGeometry g;
  g.width = raster.width;
  g.height = raster.height;
  g.resolution = raster.resolution;
  g.origin = raster.origin;
  std::vector<std::uint8_t> labels(raster.codes.size());
  for (std::size_t i = 0; i < labels.size(); ++i) labels[i] = static_cast<std::uint8_t>(codeToLabel(raster.codes[i]));
  const eval::CellEvalResult r = eval::evaluateCells(truth, g, labels, kDefaultBins, args.options);

  const nlohmann::json j = {{"truth", args.truth},
                            {"labels", args.labels},
                            {"tolerance_cells", r.tolerance_cells},
                            {"table_i",
                             {{"found", r.found},
                              {"false_positives", r.false_positives},
                              {"exact_found", r.exact_found},
                              {"found_with_displacement", r.found_displaced},
                              {"not_found", r.not_found},
                              {"ground_truth", r.ground_truth},
                              {"paper_recall", r.paper_recall},
                              {"paper_precision", r.paper_precision}}},
                            {"predicted_glass_cells", r.predicted},
                            {"truth_outside_map", r.truth_outside},
                            {"exact", scoresJson(r.exact)},
                            {"tolerant", scoresJson(r.tolerant)},
                            {"mean_angle_error_deg", r.mean_angle_error_deg},
                            {"angle_cells", r.angle_cells}};
  if (!args.json.empty()) cli::writeJsonFile(args.json, j);
  if (args.quiet) return;
  std::cout << j.dump(2) << "\n\n";
  std::printf("Table I (paper 2.5.6), tolerance %d cells\n", r.tolerance_cells);
  std::printf("  %-28s %8zu\n", "found", r.found);
  std::printf("  %-28s %8zu\n", "false positives", r.false_positives);
  std::printf("  %-28s %8zu\n", "exact found", r.exact_found);
  std::printf("  %-28s %8zu\n", "found (with displacement)", r.found_displaced);
  std::printf("  %-28s %8zu\n", "not found", r.not_found);
  std::printf("  %-28s %8zu\n", "ground truth", r.ground_truth);
  std::printf("\n  %-12s %10s %10s %10s\n", "tolerance", "precision", "recall", "F1");
  std::printf("  %-12s %10.3f %10.3f %10.3f\n", "0 cells", r.exact.precision, r.exact.recall, r.exact.f1);
  std::printf("  %-12s %10.3f %10.3f %10.3f\n", (std::to_string(r.tolerance_cells) + " cells").c_str(),
              r.tolerant.precision, r.tolerant.recall, r.tolerant.f1);
  std::printf("\n  mean pane-angle error %.2f deg over %zu cells\n", r.mean_angle_error_deg, r.angle_cells);
}

const cli::Registrar reg(70, [](CLI::App& app) {
  auto args = std::make_shared<EvalCellsArgs>();
  CLI::App& eval = cli::verb(app, "eval", "Score maps and trajectories against ground truth.");
  CLI::App* cmd =
      eval.add_subcommand("cells", "Score glass cells of a label GeoTIFF against a floorplan (paper Table I).");
  cmd->add_option("--truth", args->truth, "true floorplan (GeoJSON, GPKG, DXF, Shapefile) with glass segments")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--labels", args->labels, "label GeoTIFF written by 'glassmap map' (DIR/labels.tif)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--json", args->json, "also write the figures to this JSON file");
  cmd->add_option("--tolerance", args->options.tolerance_cells, "displacement tolerance [cells]")
      ->capture_default_str();
  cli::addUnitsOption(*cmd, args->units);
  cli::addLayersOption(*cmd, args->layers);
  cmd->add_flag("-q,--quiet", args->quiet, "print nothing (use with --json)");
  cmd->callback([args] { run(*args); });
});

}  // namespace
}  // namespace glassmap
