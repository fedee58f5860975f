// Benchmarks of the grid stage: exact traversal (cells/s, beams/s), the occupancy pass, and the
// whole grid glass mapping of the Freiburg 079 log (wall time, peak memory).
//   bench_grid [--benchmark_filter=...]    (the Freiburg run needs ../shared/data/real next to the repo)
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <filesystem>
#include <random>

#include "glassmap/glass/mapping.hpp"
#include "glassmap/grid/hit_miss_grid.hpp"
#include "glassmap/grid/traversal.hpp"
#include "glassmap/io/log.hpp"

namespace {

using namespace glassmap;

// A 100 m x 100 m floor at 5 cm and random beams of 0.5 to 30 m from inside it.
grid::GridGeometry floorGrid() { return grid::coveringGeometry(Vec2(0, 0), Vec2(100, 100), 0.05); }

std::vector<std::pair<Vec2, Vec2>> randomBeams(std::size_t n) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> pos(0.0, 100.0), ang(-kPi, kPi), len(0.5, 30.0);
  std::vector<std::pair<Vec2, Vec2>> beams(n);
  for (auto& b : beams) {
    b.first = Vec2(pos(rng), pos(rng));
    const double a = ang(rng), l = len(rng);
    b.second = b.first + l * Vec2(std::cos(a), std::sin(a));
  }
  return beams;
}

void BM_TraverseOnly(benchmark::State& state) {
  const auto g = floorGrid();
  const auto beams = randomBeams(1 << 14);
  std::size_t cells = 0, n = 0;
  for (auto _ : state) {
    const auto& [a, b] = beams[n++ & (beams.size() - 1)];
    long sum = 0;
    cells += grid::traverse(g, a, b, [&](int x, int y, double, bool) { sum += x ^ y; });
    benchmark::DoNotOptimize(sum);
  }
  state.counters["cells/s"] = benchmark::Counter(static_cast<double>(cells), benchmark::Counter::kIsRate);
  state.counters["beams/s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_TraverseOnly);

// The occupancy pass kernel: traversal with hit/miss updates in the sparse tiled grid.
void BM_TraverseCounts(benchmark::State& state) {
  const auto g = floorGrid();
  grid::HitMissGrid counts(g);
  const auto beams = randomBeams(1 << 14);
  std::size_t cells = 0, n = 0;
  for (auto _ : state) {
    const auto& [a, b] = beams[n++ & (beams.size() - 1)];
    cells += grid::traverse(g, a, b, [&](int x, int y, double, bool last) {
      if (last)
        counts.addHit(x, y);
      else
        counts.addMiss(x, y);
    });
  }
  state.counters["cells/s"] = benchmark::Counter(static_cast<double>(cells), benchmark::Counter::kIsRate);
  state.counters["beams/s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["tiles"] = static_cast<double>(counts.allocatedTiles());
}
BENCHMARK(BM_TraverseCounts);

void BM_MapFreiburg079(benchmark::State& state) {
  const std::filesystem::path log_path =
      std::filesystem::path(GLASSMAP_SOURCE_DIR) / "../shared/data/real/freiburg-079-corrected.log.gz";
  if (!std::filesystem::exists(log_path)) {
    state.SkipWithError("freiburg-079-corrected.log.gz not found");
    return;
  }
  const LaserLog log = readLog(log_path);
  glass::MappingOptions o;
  o.method = state.range(0) == 0 ? glass::Method::Heuristic : glass::Method::Direct;
  glass::MappingStats st;
  for (auto _ : state) st = glass::mapLog(log, o).stats;
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  state.counters["beams/s"] =
      benchmark::Counter(static_cast<double>(st.beams * state.iterations()), benchmark::Counter::kIsRate);
  state.counters["glass_cells"] = static_cast<double>(st.glass_cells);
  state.counters["bytes/cell"] = st.bytes_per_observed_cell;
  state.counters["peak_MB"] = static_cast<double>(usage.ru_maxrss) / 1024.0;
}
BENCHMARK(BM_MapFreiburg079)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace

BENCHMARK_MAIN();
