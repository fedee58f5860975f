// Google Benchmark: MRF solvers on the synthetic floor (lossless candidate sets), per side length.
#include <benchmark/benchmark.h>

#include "glassmap/mrf/solver.hpp"
#include "glassmap/mrf/synthetic.hpp"

namespace {

using namespace glassmap::mrf;

const LabelEnergy& instance(int side) {
  static int cached_side = -1;
  static LabelEnergy e;
  if (cached_side != side) {
    SyntheticOptions o;
    o.width = o.height = side;
    e = makeSyntheticInstance(o, psiTable(PsiKind::Closed, glassmap::kDefaultBins)).energy;
    restrictCandidates(e);
    cached_side = side;
  }
  return e;
}

void run(benchmark::State& state, SolverKind solver) {
  const LabelEnergy& e = instance(static_cast<int>(state.range(0)));
  const std::vector<uint16_t> start = argminLabels(e);
  MrfResult r;
  for (auto _ : state) {
    std::vector<uint16_t> labels = start;
    r = makeSolver(solver)->solve(e, labels);
    benchmark::DoNotOptimize(labels.data());
  }
  state.counters["energy"] = static_cast<double>(r.energy);
  state.counters["cycles"] = r.cycles;
  state.counters["cells"] = static_cast<double>(e.cells());
}

void BM_MrfIcm(benchmark::State& s) { run(s, SolverKind::Icm); }
void BM_MrfSwap(benchmark::State& s) { run(s, SolverKind::Swap); }
void BM_MrfExpansion(benchmark::State& s) { run(s, SolverKind::Expansion); }

BENCHMARK(BM_MrfIcm)->Arg(250)->Arg(500)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MrfSwap)->Arg(250)->Arg(500)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MrfExpansion)->Arg(250)->Arg(500)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
