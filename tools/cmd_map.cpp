// glassmap map LOG -o DIR: options, one pipeline::mapLog call, the files and the summary.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli_common.hpp"
#include "cli_georef.hpp"
#include "glassmap/core/atomic_file.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/io/log.hpp"
#include "glassmap/io/sensor_profile.hpp"
#include "glassmap/pipeline/map_files.hpp"
#include "glassmap/pipeline/map_log.hpp"
#include "glassmap/pipeline/reports.hpp"

namespace glassmap {
namespace {

namespace fs = std::filesystem;

struct MapArgs {
  std::string log;
  std::string out;
  std::string method = "mrf";
  std::string mrf_solver = "expansion";
  std::string mrf_psi = "pane";
  std::string no_returns = "angular";
  std::string pane_grouping = "voting";
  int laser_id = 0;
  bool quiet = false;
  bool vectorize = true;
  double max_memory_mb = 4096.0;
  std::string spool_dir;  // "": beside the output folder
  std::string sensor;
  pipeline::MapOptions options;
  LogReadOptions read;
  cli::GeorefArgs georef;  // the floorplan files in the building's CRS
};

// The deepest folder of `out`'s path that exists: where a log too large for memory is kept.
fs::path existingFolderOf(const std::string& out) {
  fs::path p = fs::absolute(out);
  std::error_code ec;
  while (!fs::is_directory(p, ec) && p.has_parent_path() && p != p.parent_path()) p = p.parent_path();
  return p;
}

void run(MapArgs& args) {
  const auto t0 = std::chrono::steady_clock::now();
  const bool show_progress = !args.quiet && cli::stderrIsTerminal();
  // Fail now, not after the whole run, when the output cannot be written.
  checkWritableDirectory(args.out);
  const std::optional<FloorplanGeoref> georef = cli::georefOf(args.georef);
  LogReadOptions read = args.read;
  read.carmen.laser_id = args.laser_id;
  read.carmen.max_memory_bytes = static_cast<std::size_t>(args.max_memory_mb * 1e6);  // the log counts too
  // A log over a quarter of the budget is kept on disk: the grid gets the rest.
  read.carmen.spool_above_bytes = read.carmen.max_memory_bytes / 4;
  read.carmen.spool_directory = args.spool_dir.empty() ? existingFolderOf(args.out) : fs::path(args.spool_dir);
  read.carmen.progress = cli::readProgress(show_progress);
  read.ros2.pose_source = BagPoseSource::Auto;  // SLAM poses (map -> odom) when the bag has them
  const LaserLog log = [&] {
    try {
      return cli::readLogReporting(args.log, read, args.quiet);
    } catch (const Error& e) {
      if (e.message().find("(the memory limit)") == std::string::npos) throw;
      throw Error(e.message() + ": raise --max-memory (now " +
                      std::to_string(static_cast<long long>(args.max_memory_mb)) + " MB) or map a part of the log",
                  e.file(), e.line(), e.field());
    }
  }();
  const double seconds_read = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const std::uint64_t on_disk = pipeline::logOnDiskBytes(log);
  if (on_disk > 0 && !args.quiet)
    std::cerr << "glassmap: the log's " << log.scanCount() << " scans need more than a quarter of --max-memory: "
              << "kept on disk (" << on_disk / 1000000 << " MB, an unnamed file in "
              << read.carmen.spool_directory.string() << ") and read back in blocks by every pass\n";

  // Options given as names are parsed here, at the edge.
  pipeline::MapOptions& options = args.options;
  options.method = pipeline::parseMapMethod(args.method);
  options.mrf.solver = mrf::parseSolver(args.mrf_solver);
  options.mrf.psi = mrf::parsePsi(args.mrf_psi);
  options.mapping.beams.no_return = grid::parseNoReturnMode(args.no_returns);
  options.vectorize.glass_voting = args.pane_grouping == "voting";
  // The grid gets what the log leaves of the budget.
  const std::size_t budget = static_cast<std::size_t>(args.max_memory_mb * 1e6);
  options.mapping.max_memory_bytes = pipeline::gridMemoryBudget(budget, log);
  options.fit_floorplan = args.vectorize;
  if (!args.sensor.empty()) options.sensor = readSensorProfile(args.sensor);
  const bool use_mrf = options.method == pipeline::MapMethod::Mrf;
  auto progress = [&](const char* stage, double f) {
    if (!show_progress) return;
    const std::string_view s(stage);
    if (s == "counts" || s == "angles") {
      std::fprintf(stderr, "\r%-8s %5.1f%%", stage, 100.0 * f);
      if (f >= 1.0) std::fputc('\n', stderr);
    } else if (f <= 0.0) {
      std::fprintf(stderr, "%s...\n", stage);
    }
  };
  const pipeline::MapResult result = pipeline::mapLog(log, options, progress);
  const glass::CellEvidence& e = result.evidence;
  const vector::VectorizeResult& floorplan = result.floorplan;
  const mrf::RefineResult& refined = result.mrf;
  const glass::PhantomStats& phantom = result.phantoms;

  const fs::path dir(args.out);
  const std::vector<fs::path> files = pipeline::writeMapFiles(dir, result, args.vectorize, georef ? &*georef : nullptr);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const std::size_t peak = pipeline::peakMemoryBytes();

  const auto& st = result.stats;
  pipeline::MapRunInfo info{args.log, seconds_read, seconds, peak, on_disk, {}};
  for (const fs::path& f : files) info.files.push_back(f.filename().string());
  // Written last: a folder with a stats.json holds the complete set it lists.
  cli::writeJsonFile(dir / pipeline::kMapManifest, pipeline::mapStatsJson(result, options, info));

  if (!args.quiet) {
    std::printf("%-22s %s\n", "method", args.method.c_str());
    std::printf("%-22s %zu\n", "scans", st.scans);
    std::printf("%-22s %s: %s\n", "sensor",
                result.calibrated ? "calibrated" : (options.sensor ? args.sensor.c_str() : "default profile"),
                cli::profileSummary(result.profile).c_str());
    std::printf("%-22s %zu\n", "beams", st.beams);
    std::printf("%-22s %d x %d (%.3f m)\n", "grid", e.geometry.width, e.geometry.height, e.geometry.resolution);
    std::printf("%-22s %zu\n", "cells observed", st.observed_cells);
    std::printf("%-22s %zu\n", "cells occupied", st.occupied_cells);
    std::printf("%-22s %zu\n", "glass cells", st.glass_cells);
    std::printf("%-22s %.1f\n", "state bytes/cell", st.bytes_per_observed_cell);
    if (use_mrf) std::printf("%-22s %zu cells changed\n", "mrf", refined.changed);
    if (options.prune_unfitted_glass)
      std::printf("%-22s %zu glass cells off every glass segment relabelled, %zu cells on one made glass\n", "pane fit",
                  result.pruned_glass, result.filled_glass);
    if (options.scan_fit.enabled && result.has_floorplan)
      std::printf("%-22s %s\n", "walls onto returns", cli::scanFitSummary(result.scan_fit).c_str());
    if (options.scan_clutter.enabled && result.has_floorplan)
      std::printf("%-22s %s\n", "clutter from returns", cli::scanClutterSummary(result.scan_clutter).c_str());
    if (options.sparse_panes)
      std::printf(
          "%-22s %zu found, %.1f m (%zu runs of %zu weak returns tested; rejected: %zu chance, %zu opaque, "
          "%zu too faint, %zu no lobe, %zu transient, %zu through another pane, %zu along a stronger one)\n",
          "sparse panes", result.sparse.panes, result.sparse.metres, result.sparse.runs_tested,
          result.sparse.weak_returns, result.sparse.rejected_chance, result.sparse.rejected_opaque,
          result.sparse.rejected_faint, result.sparse.rejected_unspecific,
          result.sparse.rejected_transient + result.sparse.rejected_one_visit + result.sparse.rejected_place,
          result.sparse.rejected_through, result.sparse.rejected_duplicate);
    if (options.opaque_glass)
      std::printf(
          "%-22s %zu of %zu glass cells relabelled (the beams crossing them stop just behind, or %zu panes of %zu "
          "came and went: people)\n",
          "opaque glass", result.opaque.relabelled, result.opaque.glass_cells, result.opaque.transient_panes,
          result.opaque.panes_tested);
    if (options.phantoms)
      std::printf("%-22s %zu cells cleared (%zu of %zu beams through glass folded)\n", "mirror phantoms",
                  phantom.cells_cleared, phantom.folded_beams, phantom.beams_through_glass);
    if (args.vectorize)
      std::printf("%-22s %zu glass, %zu wall\n", "segments", floorplan.map.count(Material::Glass),
                  floorplan.map.count(Material::Wall));
    std::printf(
        "%-22s %.2f (read %.2f, calibration %.2f; last pass: counts %.2f, angles %.2f, classify %.2f, mrf %.2f, "
        "sparse panes %.2f, opaque %.2f, phantoms %.2f, vectorize %.2f)\n",
        "seconds", seconds, seconds_read, result.seconds.calibration, st.seconds_counts, st.seconds_angles,
        st.seconds_classify, refined.seconds, result.seconds.sparse, result.seconds.opaque, result.seconds.phantoms,
        floorplan.stats.seconds);
    std::printf("%-22s %.1f MB\n", "peak memory", static_cast<double>(peak) / 1e6);
    std::printf("%-22s %s/{map.yaml,map.pgm,labels.tif,map.png,sensor.yaml,stats.json%s}\n", "wrote",
                dir.string().c_str(), args.vectorize ? ",floorplan.{gpkg,geojson,dxf,svg,png}" : "");
  }
}

const cli::Registrar reg(40, [](CLI::App& app) {
  auto args = std::make_shared<MapArgs>();
  auto& o = args->options.mapping;
  CLI::App* cmd = app.add_subcommand(
      "map",
      "Map a laser log into an occupancy grid with glass cells (paper 2.5.3-2.5.5) and a vector floorplan:\n"
      "DIR/map.yaml + map.pgm (ROS, glass as occupied), labels.tif (GeoTIFF codes), map.png, sensor.yaml\n"
      "(the fitted sensor profile), stats.json, "
      "floorplan.{gpkg,geojson,dxf,svg,png}.");
  cmd->add_option("log", args->log,
                  std::string(cli::kLogHelp) +
                      " with SLAM-corrected laser poses (bags: map -> odom in /tf when "
                      "present, else odometry alone, with a warning)")
      ->required()
      ->check(CLI::ExistingPath);
  cli::addLogOptions(*cmd, args->read);
  cmd->add_option("-o,--output", args->out, "output directory")->required();
  cmd->add_option(
         "--method", args->method,
         "heuristic (paper 2.5.3) | direct (direct-reflection classifier, 2.5.4) | mrf (direct, then the MRF, 2.5.5)")
      ->check(CLI::IsMember({"heuristic", "direct", "mrf"}))
      ->capture_default_str();
  cmd->add_option("--mrf-solver", args->mrf_solver, "mrf: swap | expansion | icm")
      ->check(CLI::IsMember({"swap", "expansion", "icm"}))
      ->capture_default_str();
  cmd->add_option(
         "--mrf-psi", args->mrf_psi,
         "mrf: pairwise table: paper (OCC free next to glass) | closed (glass next to OCC costs 0.6 too) | neutral |\n"
         "pane (glass borders cost by direction: nothing across the pane, 0.6 where it would go on)")
      ->check(CLI::IsMember({"paper", "closed", "neutral", "pane"}))
      ->capture_default_str();
  cmd->add_option("--mrf-weight", args->options.mrf.unary_weight, "mrf: weight of the -log posteriors against Psi")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_flag("!--no-vector", args->vectorize,
                "write no floorplan files (the floorplan is still fitted in memory for the pane fit,\n"
                "unless --keep-unfitted-glass)");
  cmd->add_flag("!--keep-unfitted-glass", args->options.prune_unfitted_glass,
                "leave the glass cells as the classifiers drew them: by default glass cells that no fitted\n"
                "glass segment explains take their best non-glass label (people walking by leave arcs of cells\n"
                "that each look like glass), and the empty or unknown cells a fitted glass segment passes\n"
                "through become glass (a faint pane draws one cell in three: a planner would drive through the\n"
                "gaps)");
  cmd->add_flag("!--no-scan-fit", args->options.scan_fit.enabled,
                "keep the walls where the cells draw them: by default each wall and clutter segment of the\n"
                "floorplan moves along its normal (its direction kept) onto the densest 0.1 m wide band of the\n"
                "returns under 8 m nearest to it (within 0.2 m; both wider for a laser noisier than 2.5 cm),\n"
                "when that band holds 2% more of them than the one about the line as drawn and no fewer lie\n"
                "within 0.1 m; corners, T junctions and doors follow");
  cmd->add_flag("!--no-scan-clutter", args->options.scan_clutter.enabled,
                "keep the clutter layer the cells draw (the outline of every occupied blob): by default it is\n"
                "replaced by segments chosen to explain the returns under 8 m that the walls and panes leave\n"
                "(a greedy cover: lines fitted through dense returns, grown while their returns leave no gap over\n"
                "0.5 m and the line crosses no free space over 0.15 m, each taken while it explains at least\n"
                "--clutter-min-share of all the returns; returns in free space, people walking, count for none;\n"
                "where those lines would explain less than the cells' pieces did, pieces come back until they do not)");
  cmd->add_option("--clutter-min-share", args->options.scan_clutter.min_share,
                  "the share of the log's returns under 8 m a clutter segment must explain to be drawn")
      ->capture_default_str()
      ->check(CLI::Range(1e-6, 1.0));
  cmd->add_flag("--sparse-panes,!--no-sparse-panes", args->options.sparse_panes,
                "look for panes too faint for the cell classifiers (a laser whose glass returns rarely, only\n"
                "near the normal; on by default, --no-sparse-panes skips it): returns from cells most beams\n"
                "cross, each along a beam nearly normal to the line they form, are grouped by line votes; a run\n"
                "along a line is drawn as glass when chance does not explain it (a contrario), the beams meeting\n"
                "it mostly pass it, its near-normal beams do not return scan by scan (people walking by answer\n"
                "every beam while there, a pane each beam on its own), and its returns did not come through\n"
                "another pane");
  cmd->add_flag("!--keep-opaque-glass", args->options.opaque_glass,
                "keep glass cells the beams do not pass: by default, a glass cell whose crossing beams mostly\n"
                "stop within max(0.3 m, 5 range sigma) behind its pane (the front of a wall seen at grazing\n"
                "incidence) takes its best non-glass label");
  cmd->add_flag("!--keep-phantoms", args->options.phantoms,
                "keep mirror phantoms: by default, wall and glass cells whose returns mostly ran straight\n"
                "through a pane and then through a wall (impossible unless the pane folded the beam) become unknown");
  cmd->add_option("--phantom-fraction", args->options.phantom.min_folded_fraction,
                  "share of a cell's returns that must be folded for it to count as a mirror phantom")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--phantom-margin", args->options.phantom.block_margin,
                  "the wall behind the pane must lie at least this far before the reading [m]")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--resolution", o.resolution, "cell size [m]")->capture_default_str()->check(CLI::PositiveNumber);
  cmd->add_option("--max-memory", args->max_memory_mb,
                  "memory budget [MB]: the log in memory (counted while reading) plus the grid's dense\n"
                  "layers (checked before they are allocated); a run over it stops with the figure. A log\n"
                  "(CARMEN or ROS 2 bag) whose scans need more than a quarter of it is kept on disk (see\n"
                  "--spool-dir) and read back block by block in every pass")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--spool-dir", args->spool_dir,
                  "folder for the scans of a log too large for memory (an unnamed temporary file, gone when\n"
                  "the run ends however it ends); default: the output folder's parent. Avoid a tmpfs: it is memory")
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--angle-bin", o.angle_bin_deg, "incidence-angle bin width [deg], divides 180")
      ->capture_default_str();
  cmd->add_option("--range-cap", o.beams.range_cap, "use beams up to this range; max-range readings clear to it [m]")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--no-return-range", o.beams.no_return_range,
                  "max-range and no-return readings clear free space up to this range [m]; 0: the range cap")
      ->capture_default_str();
  cmd->add_option("--no-returns", args->no_returns,
                  "what a reading without an echo crossed: angular (every cell up to the first one that\n"
                  "returned beams of its direction, where it may have been a dropout: a pane met at a slant\n"
                  "is crossed, a wall that drops echoes is not) | open (everything up to the clearing range)")
      ->check(CLI::IsMember({"open", "angular"}))
      ->capture_default_str();
  cmd->add_option("--miss-margin", o.beams.miss_margin, "no miss counted this close before a reading [m]")
      ->capture_default_str();
  cmd->add_option("--pane-grouping", args->pane_grouping,
                  "how glass cells become panes: voting (cells vote for lines near their angle labels:\n"
                  "finds panes seen in one cell of three) | regions (region growing over neighbouring cells)")
      ->check(CLI::IsMember({"voting", "regions"}))
      ->capture_default_str();
  cmd->add_option("--laser-id", args->laser_id, "keep only scans of this CARMEN laser (0: all)")->capture_default_str();
  cmd->add_option("--sigmoid-margin", o.direct.sigmoid_margin, "direct: sigmoid margin delta [cells]")
      ->capture_default_str();
  cmd->add_option("--direct-sigma", o.direct.direct_sigma_deg, "direct: direct-reflection lobe sigma [deg]")
      ->capture_default_str();
  cmd->add_option("--direct-peak", o.direct.direct_peak, "direct: P(return) at normal incidence")
      ->capture_default_str();
  cmd->add_option("--prior-glass", o.direct.prior_glass, "direct: prior of glass for a hit cell")
      ->capture_default_str();
  cmd->add_option("--prior-occupied", o.direct.prior_occupied, "direct: prior of OCC for a hit cell")
      ->capture_default_str();
  cmd->add_option("--p-hit-empty", o.direct.p_hit_emp, "direct: P(beam ends in an empty cell)")->capture_default_str();
  cmd->add_flag("--p-hit-empty-from-log,!--fixed-p-hit-empty", o.direct.p_hit_emp_from_log,
                "direct: estimate P(beam ends in an empty cell) from the hits in the log's empty space (for buildings "
                "without people: faint panes come out, but people's tracks are drawn as glass)")
      ->capture_default_str();
  cmd->add_option("--p-hit-occupied", o.direct.p_hit_occ, "direct: P(beam ends in an occupied cell it reaches)")
      ->capture_default_str();
  cmd->add_option("--min-glass-hits", o.direct.min_glass_hits, "direct: hits a cell needs to be glass")
      ->capture_default_str();
  cmd->add_option("--heuristic-min-hits", o.heuristic.min_hits, "heuristic: hits in the angle window")
      ->capture_default_str();
  cmd->add_option("--heuristic-min-misses", o.heuristic.min_other_misses, "heuristic: misses outside the window")
      ->capture_default_str();
  cmd->add_option("--sensor", args->sensor,
                  "sensor profile YAML (from `glassmap calibrate`, or a map folder's sensor.yaml): its range\n"
                  "noise and glass lobe set the thresholds; one pass, no calibration")
      ->check(CLI::ExistingFile);
  cmd->add_flag("!--no-calibrate", args->options.calibrate,
                "map once with the default thresholds (a 1-2 cm laser with a 2 deg glass lobe). By default\n"
                "the range noise is estimated from neighbouring readings within scans, a first pass maps\n"
                "the log with the margins it sets, the rest of the sensor profile is fitted against its\n"
                "floorplan (as `glassmap calibrate`; panes whose beams return scan by scan, people walking\n"
                "by, are left out), and the log is mapped again when the profile's glass lobe changes the\n"
                "thresholds (see --profile-lobe).\n"
                "Options given explicitly (--direct-sigma, --miss-margin, ...) are kept either way");
  cmd->add_flag("--profile-lobe,!--no-profile-lobe", args->options.profile_lobe,
                "the profile's glass lobe (peak, sigma, floor) replaces the classifier's defaults (on by\n"
                "default; --no-profile-lobe keeps the 2 deg / 0.9 lobe and lets only the range-noise thresholds\n"
                "follow the profile). A lobe the calibration could not fit (too few beams on glass, after\n"
                "--lobe-search if given), one wider than glass shows (sigma - 2 se > 20 deg: door frames taken for\n"
                "panes) or one fainter (peak + 2 se < 0.05) keeps the defaults, said among the calibration\n"
                "warnings (docs/calibration.md)");
  cmd->add_flag("--lobe-search,!--no-lobe-search", args->options.lobe_search,
                "when the first pass leaves too few beams on glass to fit the lobe, map the log once more with\n"
                "a broad lobe (peak 0.5, sigma 10 deg, floor 0.1) and fit the lobe against that floorplan (off\n"
                "by default since the first pass has the range noise and sees faint panes; docs/calibration.md)");
  cmd->add_option("--calibration-rounds", args->options.calibration_rounds,
                  "fit and re-map at most this many times: a fit within one standard error of the last\n"
                  "(lobe peak, sigma, floor) ends it, its map kept; so does a first fit within one standard\n"
                  "error of the first pass's lobe (floors at or below the spurious rate count as equal): the\n"
                  "first pass is the map and the profile keeps its lobe (said among the calibration warnings)")
      ->capture_default_str()
      ->check(CLI::Range(1, 5));
  cli::addGeorefOptions(*cmd, args->georef);
  cmd->add_flag("-q,--quiet", args->quiet, "no progress, no summary");
  cmd->callback([args] { run(*args); });
});

}  // namespace
}  // namespace glassmap
