// Benchmarks of vectorisation (label raster -> floorplan) on the mapped office-floor scene and on
// the mapped Freiburg 079 log. The label grids are built once per run (simulate + map, or map the
// real log), then only vectorize() is timed.
//   bench_vector [--benchmark_filter=...]    (Freiburg needs ../shared/data/real next to the repo)
#include <benchmark/benchmark.h>

#include <filesystem>
#include <memory>

#include "glassmap/glass/mapping.hpp"
#include "glassmap/io/floorplan.hpp"
#include "glassmap/io/log.hpp"
#include "glassmap/sim/scene.hpp"
#include "glassmap/sim/simulator.hpp"
#include "glassmap/vector/from_evidence.hpp"
#include "glassmap/vector/vectorize.hpp"

namespace {

using namespace glassmap;
namespace fs = std::filesystem;

const vector::LabelGrid& officeFloorLabels() {
  static const std::unique_ptr<vector::LabelGrid> grid = [] {
    const sim::Scene scene = sim::loadScene(fs::path(GLASSMAP_SOURCE_DIR) / "maps/office-floor/scene.yaml");
    sim::SimOptions so;
    so.seed = 1;
    const sim::SimResult run = sim::simulate(scene, so);
    return std::make_unique<vector::LabelGrid>(vector::toLabelGrid(glass::mapLog(run.log, {}).evidence));
  }();
  return *grid;
}

const vector::LabelGrid* freiburgLabels() {
  static const std::unique_ptr<vector::LabelGrid> grid = []() -> std::unique_ptr<vector::LabelGrid> {
    const fs::path log = fs::path(GLASSMAP_SOURCE_DIR) / "../shared/data/real/freiburg-079-corrected.log.gz";
    if (!fs::exists(log)) return nullptr;
    return std::make_unique<vector::LabelGrid>(vector::toLabelGrid(glass::mapLog(readLog(log), {}).evidence));
  }();
  return grid.get();
}

void run(benchmark::State& state, const vector::LabelGrid& grid) {
  vector::VectorizeResult r;
  for (auto _ : state) {
    r = vector::vectorize(grid);
    benchmark::DoNotOptimize(r.map.segments.data());
  }
  state.counters["cells"] = static_cast<double>(grid.cells());
  state.counters["glass_cells"] = static_cast<double>(r.stats.glass_cells);
  state.counters["wall_cells"] = static_cast<double>(r.stats.wall_cells);
  state.counters["glass_segments"] = static_cast<double>(r.map.count(Material::Glass));
  state.counters["wall_segments"] = static_cast<double>(r.map.count(Material::Wall));
}

void BM_VectorizeOfficeFloor(benchmark::State& state) { run(state, officeFloorLabels()); }
BENCHMARK(BM_VectorizeOfficeFloor)->Unit(benchmark::kMillisecond);

void BM_VectorizeFreiburg079(benchmark::State& state) {
  const vector::LabelGrid* grid = freiburgLabels();
  if (!grid) {
    state.SkipWithError("freiburg-079-corrected.log.gz not found next to the repository");
    return;
  }
  run(state, *grid);
}
BENCHMARK(BM_VectorizeFreiburg079)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
