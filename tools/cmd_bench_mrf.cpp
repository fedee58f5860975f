// glassmap bench mrf: MRF solvers (ICM, swap, expansion) on a synthetic 38-label floor or on an
// instance file; prints energy, cycles and seconds per solver.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_common.hpp"
#include "glassmap/core/atomic_file.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/mrf/solver.hpp"
#include "glassmap/mrf/synthetic.hpp"

namespace glassmap {
namespace {

struct BenchMrfArgs {
  mrf::SyntheticOptions synth;
  std::string instance;  // read this instead of generating
  std::string psi = "closed";
  std::vector<std::string> solvers = {"icm", "swap", "expansion"};
  std::string write_instance, csv, json;
  bool dense = false;      // no candidate sets
  int64_t margin = -1;     // candidate margin [cost units], -1 = lossless
  bool reference = false;  // also run swap to full convergence
  mrf::MrfOptions options;
};

void writeText(const std::string& path, const std::string& text) {
  writeAtomically(path, [&](const std::filesystem::path& tmp) {
    std::ofstream out(tmp);
    out << text;
    if (!out.flush()) throw Error("cannot write", tmp.string());
  });
}

void run(const BenchMrfArgs& args) {
  mrf::LabelEnergy e;
  std::vector<uint16_t> truth;
  if (args.instance.empty()) {
    const mrf::PsiKind kind = mrf::parsePsi(args.psi);
    auto inst = mrf::makeSyntheticInstance(args.synth, mrf::psiTable(kind, kDefaultBins));
    e = std::move(inst.energy);
    e.pairwise_dir = mrf::psiDirectionTables(kind, kDefaultBins);  // empty unless direction-dependent
    truth = std::move(inst.truth);
  } else {
    e = mrf::readInstance(args.instance);
  }
  if (!args.write_instance.empty()) mrf::writeInstance(args.write_instance, e);
  const std::size_t pairs = args.dense ? e.cells() * e.num_labels : mrf::restrictCandidates(e, args.margin);
  if (args.dense) e.candidates.clear();
  std::size_t movable = 0;
  for (std::size_t c = 0; c < e.cells(); ++c)
    movable += e.isActive(c) && (e.candidates.empty() || (e.candidates[c] & (e.candidates[c] - 1)) != 0);
  std::printf("instance %dx%d, %d labels, psi %s; candidate pairs %zu (%.1f%%), movable cells %zu\n", e.width, e.height,
              e.num_labels, args.instance.empty() ? args.psi.c_str() : "file", pairs,
              100.0 * pairs / (double(e.cells()) * e.num_labels), movable);

  const std::vector<uint16_t> start = mrf::argminLabels(e);
  struct Row {
    std::string name;
    mrf::MrfResult r;
    mrf::GlassScore s;
  };
  std::vector<Row> rows;
  auto runOne = [&](const std::string& label, const std::string& solver, const mrf::MrfOptions& o) {
    std::vector<uint16_t> labels = start;
    const mrf::MrfResult r = mrf::makeSolver(mrf::parseSolver(solver), o)->solve(e, labels);
    const int64_t check = mrf::energy(e, labels);
    if (check != r.energy)
      throw Error(label + ": tracked energy " + std::to_string(r.energy) + " != recomputed " + std::to_string(check));
    rows.push_back({label, r, truth.empty() ? mrf::GlassScore{} : mrf::scoreGlass(truth, labels)});
  };
  if (!truth.empty()) rows.push_back({"truth", {}, mrf::scoreGlass(truth, truth)});
  if (!truth.empty()) rows.back().r.energy = mrf::energy(e, truth);
  rows.push_back({"start", {}, truth.empty() ? mrf::GlassScore{} : mrf::scoreGlass(truth, start)});
  rows.back().r.energy = mrf::energy(e, start);
  for (const auto& s : args.solvers) runOne(s, s, args.options);
  int64_t ref = 0;
  if (args.reference) {
    mrf::MrfOptions o = args.options;
    o.min_cycle_gain = 0.0;
    o.max_cycles = 1000;
    runOne("swap-converged", "swap", o);
    ref = rows.back().r.energy;
  }

  const int64_t start_energy = mrf::energy(e, start);
  std::printf("start (unary argmin) energy %lld\n", static_cast<long long>(start_energy));
  std::printf("%-15s %14s %9s %6s %9s %8s %8s %5s %8s %7s %7s %7s\n", "solver", "energy", "gap%", "cycles", "moves",
              "wall_s", "cpu_s", "conv", "glassF1", "found", "gls>occ", "gls>emp");
  nlohmann::json jrows = nlohmann::json::array();
  std::ostringstream csv;
  csv << "solver,energy,gap_percent,cycles,moves,seconds,cpu_seconds,converged,truncated_terms,glass_f1,"
         "angle_correct,glass_to_occ,glass_to_emp,truth_glass\n";
  for (const Row& row : rows) {
    const double gap = ref != 0 ? 100.0 * double(row.r.energy - ref) / double(ref) : 0.0;
    const bool scored = !truth.empty();
    std::printf("%-15s %14lld %9.4f %6d %9lld %8.3f %8.3f %5s %8.4f %7lld %7lld %7lld\n", row.name.c_str(),
                static_cast<long long>(row.r.energy), gap, row.r.cycles, static_cast<long long>(row.r.moves),
                row.r.seconds, row.r.cpu_seconds, row.r.converged ? "yes" : "no", scored ? row.s.f1() : 0.0,
                static_cast<long long>(row.s.found_glass), static_cast<long long>(row.s.glass_to_occ),
                static_cast<long long>(row.s.glass_to_emp));
    jrows.push_back({{"solver", row.name},
                     {"energy", row.r.energy},
                     {"gap_percent", gap},
                     {"cycles", row.r.cycles},
                     {"moves", row.r.moves},
                     {"seconds", row.r.seconds},
                     {"cpu_seconds", row.r.cpu_seconds},
                     {"converged", row.r.converged},
                     {"truncated_terms", row.r.truncated_terms},
                     {"glass_f1", row.s.f1()},
                     {"angle_correct", row.s.angle_correct},
                     {"glass_to_occ", row.s.glass_to_occ},
                     {"glass_to_emp", row.s.glass_to_emp},
                     {"truth_glass", row.s.truth_glass}});
    csv << row.name << ',' << row.r.energy << ',' << gap << ',' << row.r.cycles << ',' << row.r.moves << ','
        << row.r.seconds << ',' << row.r.cpu_seconds << ',' << row.r.converged << ',' << row.r.truncated_terms << ','
        << row.s.f1() << ',' << row.s.angle_correct << ',' << row.s.glass_to_occ << ',' << row.s.glass_to_emp << ','
        << row.s.truth_glass << '\n';
  }
  if (!args.csv.empty()) writeText(args.csv, csv.str());
  if (!args.json.empty()) {
    const nlohmann::json j = {{"width", e.width},
                              {"height", e.height},
                              {"labels", e.num_labels},
                              {"psi", args.instance.empty() ? args.psi : "file"},
                              {"candidate_pairs", pairs},
                              {"movable_cells", movable},
                              {"start_energy", start_energy},
                              {"results", jrows}};
    cli::writeJsonFile(args.json, j);
  }
}

const cli::Registrar reg(80, [](CLI::App& app) {
  CLI::App& bench = cli::verb(app, "bench", "Benchmarks that print speed and accuracy figures");
  auto args = std::make_shared<BenchMrfArgs>();
  CLI::App* sub = bench.add_subcommand("mrf",
                                       "MRF solvers (icm, swap, expansion) on a synthetic "
                                       "38-label floor or an instance file");
  sub->add_option("--width", args->synth.width, "synthetic floor width [cells]")->capture_default_str();
  sub->add_option("--height", args->synth.height, "synthetic floor height [cells]")->capture_default_str();
  sub->add_option("--seed", args->synth.seed, "synthetic floor seed")->capture_default_str();
  sub->add_option("--noise", args->synth.noise, "unary noise near structure [nats]")->capture_default_str();
  sub->add_option("--unary-scale", args->synth.unary_scale, "synthetic classifier confidence factor")
      ->capture_default_str();
  sub->add_option("--psi", args->psi, "pairwise table: paper | closed | neutral | pane")->capture_default_str();
  sub->add_option("--instance", args->instance, "read this binary instance instead of generating");
  sub->add_option("--solvers", args->solvers, "solvers to run, in order")->capture_default_str();
  sub->add_option("--max-cycles", args->options.max_cycles, "cycle limit")->capture_default_str();
  sub->add_option("--min-gain", args->options.min_cycle_gain, "stop when a cycle gains less than this fraction of E")
      ->capture_default_str();
  sub->add_flag("--dense", args->dense, "every label a candidate everywhere (no pruning)");
  sub->add_option("--margin", args->margin, "candidate margin over the best unary [cost units]; -1 = lossless pruning")
      ->capture_default_str();
  sub->add_flag("--reference", args->reference, "also run swap to full convergence; gap% is to it");
  sub->add_option("--write-instance", args->write_instance,
                  "write the instance (uint32 w,h,labels; int32 unary, pairwise; little-endian)");
  sub->add_option("--csv", args->csv, "write results as CSV");
  sub->add_option("--json", args->json, "write results as JSON");
  sub->callback([args] { run(*args); });
});

}  // namespace
}  // namespace glassmap
