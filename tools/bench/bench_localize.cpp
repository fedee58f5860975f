// MCL update cost (predict + weight + resample) on the simulated office-floor scene: the issue's
// 2,500 particles x 61 beams with the glass model (its mirrored and continued rays included) on
// one and two threads, and 500 particles x 15 beams for every model. Reports updates/s.
//
//   build-loc/tools/bench_localize [--benchmark_filter=...]
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <memory>

#include "glassmap/localize/localizer.hpp"
#include "glassmap/sim/simulator.hpp"

namespace {

using namespace glassmap;

struct Fixture {
  sim::Scene scene;
  sim::SimResult sim;
  Fixture() {
    scene = sim::loadScene(std::string(GLASSMAP_SOURCE_DIR) + "/maps/office-floor/scene.yaml");
    sim::SimOptions o;
    o.seed = 1;
    o.duration_limit = 20.0;  // 200 scans along the main corridor, glass on the way
    sim = sim::simulate(scene, o);
  }
};

const Fixture& fixture() {
  static const Fixture f;
  return f;
}

// Arguments: particles, beams, threads. The model comes from the benchmark's name.
void runUpdates(benchmark::State& state, const std::string& model_name) {
  const Fixture& f = fixture();
  const auto particles = static_cast<int>(state.range(0));
  const auto beams = static_cast<int>(state.range(1));
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(state.range(2)));
  sensor::SensorParams sp;
  sp.max_range = f.scene.laser.max_range;
  const auto model = sensor::makeSensorModel(model_name, f.scene.map, sp);
  localize::FilterOptions fo;
  fo.max_particles = particles;
  fo.adaptive = false;  // a fixed count: the figure is per particle count
  localize::ParticleFilter filter(*model, fo);
  filter.initialize(f.sim.ground_truth.front().pose, 0.1, deg2rad(3));
  std::vector<sensor::BeamSet> sets;
  for (const LaserScan& s : f.sim.log.scans) sets.push_back(sensor::makeBeamSet(s, beams));
  // The log is played forward, then backward, and so on: every step is a real odometry step
  // (the robot driving its path back), so the filter keeps tracking and the cost per update stays
  // that of a tracking filter. (Restarting at the first scan would apply the jump from the last
  // scan's odometry to the first's, lose the filter and change the cost by 5-15%.)
  const std::size_t n = f.sim.log.scans.size();
  std::size_t k = 0;
  bool forward = true;
  for (auto _ : state) {
    if (forward && k + 1 == n) forward = false;
    if (!forward && k == 0) forward = true;
    const std::size_t next = forward ? k + 1 : k - 1;
    filter.predict(localize::odometryDelta(f.sim.log.scans[k].odom_pose, f.sim.log.scans[next].odom_pose));
    filter.correct(sets[next]);
    k = next;
  }
  // A benchmark that lost the robot measures something else: say so.
  // ground_truth holds the true laser pose of each scan (the estimate is the laser pose too).
  const double error = (filter.estimate().t - f.sim.ground_truth[k].pose.t).norm();
  state.counters["final_error_m"] = error;  // printed with SI prefixes: 4.6m = 4.6 mm
  state.SetItemsProcessed(state.iterations());
  state.counters["updates/s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["beam evals/s"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * particles * static_cast<double>(sets[0].size()),
                         benchmark::Counter::kIsRate);
}

void BM_Update_glass(benchmark::State& s) { runUpdates(s, "glass"); }
void BM_Update_glass_paper(benchmark::State& s) { runUpdates(s, "glass-paper"); }
void BM_Update_beam(benchmark::State& s) { runUpdates(s, "beam"); }
void BM_Update_field(benchmark::State& s) { runUpdates(s, "field"); }

BENCHMARK(BM_Update_glass)
    ->Args({2500, 61, 1})
    ->Args({2500, 61, 2})
    ->Args({500, 15, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_Update_field)
    ->Args({2500, 61, 1})
    ->Args({2500, 61, 2})
    ->Args({500, 15, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_Update_beam)->Args({2500, 61, 1})->Args({500, 15, 1})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Update_glass_paper)->Args({500, 15, 1})->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
