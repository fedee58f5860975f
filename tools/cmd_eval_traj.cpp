// glassmap eval traj --truth GT.tum EST.tum: absolute trajectory error (ATE) as evo prints it.
#include <cstdio>
#include <nlohmann/json.hpp>

#include "cli_common.hpp"
#include "glassmap/core/atomic_file.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/eval/trajectory.hpp"
#include "glassmap/io/tum.hpp"

namespace glassmap {
namespace {

struct EvalTrajArgs {
  std::string truth, estimate, json, errors;
  eval::TrajectoryEvalOptions options;
  bool quiet = false;
};

void run(const EvalTrajArgs& a) {
  const auto truth = readTum(a.truth);
  const auto estimate = readTum(a.estimate);
  const eval::TrajectoryErrors r = eval::evaluateTrajectory(truth, estimate, a.options);
  const nlohmann::json stats = {{"rmse", r.rmse},
                                {"mean", r.mean},
                                {"median", r.median},
                                {"std", r.std},
                                {"min", r.min},
                                {"max", r.max},
                                {"heading_mean_deg", r.heading_mean_deg},
                                {"heading_max_deg", r.heading_max_deg},
                                {"fraction_under", r.fraction_under},
                                {"good_error", r.good_error},
                                {"matched", r.matched},
                                {"unmatched", r.unmatched}};
  if (!a.json.empty()) cli::writeJsonFile(a.json, stats);
  if (!a.errors.empty()) {
    writeAtomically(a.errors, [&](const std::filesystem::path& tmp) {
      std::FILE* f = std::fopen(tmp.c_str(), "w");
      if (f == nullptr) throw Error("cannot write", a.errors);
      std::fprintf(f, "t,position_error_m,heading_error_deg\n");
      for (std::size_t i = 0; i < r.times.size(); ++i)
        std::fprintf(f, "%.6f,%.6f,%.4f\n", r.times[i], r.position_errors[i], r.heading_errors_deg[i]);
      const bool ok = std::ferror(f) == 0;
      if (std::fclose(f) != 0 || !ok) throw Error("cannot write", a.errors);
    });
  }
  if (!a.quiet) {
    std::printf("APE w.r.t. translation part (m), %zu poses matched, %zu unmatched\n", r.matched, r.unmatched);
    std::printf("  %-16s %10.4f\n", "max", r.max);
    std::printf("  %-16s %10.4f\n", "mean", r.mean);
    std::printf("  %-16s %10.4f\n", "median", r.median);
    std::printf("  %-16s %10.4f\n", "min", r.min);
    std::printf("  %-16s %10.4f\n", "rmse", r.rmse);
    std::printf("  %-16s %10.4f\n", "std", r.std);
    std::printf("  %-16s %10.3f\n", "heading mean deg", r.heading_mean_deg);
    std::printf("  %-16s %10.3f\n", "heading max deg", r.heading_max_deg);
    std::printf("  %-16s %10.3f  (error < %.2f m)\n", "time fraction", r.fraction_under, r.good_error);
  }
}

const cli::Registrar reg(72, [](CLI::App& app) {
  CLI::App& eval = cli::verb(app, "eval", "Score maps and trajectories against ground truth");
  auto a = std::make_shared<EvalTrajArgs>();
  CLI::App* sub = eval.add_subcommand(
      "traj",
      "Absolute trajectory error of an estimate (TUM) against ground truth (TUM), both in the map\n"
      "frame (no alignment): RMSE, mean, median, std, min, max of the position error, heading error\n"
      "and the fraction of time under a threshold.");
  sub->add_option("estimate", a->estimate, "estimated trajectory (TUM)")->required()->check(CLI::ExistingFile);
  sub->add_option("--truth", a->truth, "ground-truth trajectory (TUM)")->required()->check(CLI::ExistingFile);
  sub->add_option("--json", a->json, "write the statistics as JSON (stats.json, evo's keys)");
  sub->add_option("--errors", a->errors,
                  "also write the error of every matched estimate as CSV: t, position_error_m, heading_error_deg");
  sub->add_option("--max-time-diff", a->options.max_time_diff, "timestamp association tolerance [s]")
      ->capture_default_str();
  sub->add_option("--good-error", a->options.good_error, "threshold of the time fraction [m]")->capture_default_str();
  sub->add_flag("-q,--quiet", a->quiet, "print nothing on success");
  sub->callback([a] { run(*a); });
});

}  // namespace
}  // namespace glassmap
