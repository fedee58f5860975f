// MCL update cost (predict + weight + resample) on the simulated office-floor scene: the issue's
// 2,500 particles x 61 beams per model on one and two threads, and 500 particles x 15 beams.
//
// Every benchmark iteration is the same work: a fresh filter (same seed) at the first scan's true
// pose, then one update per scan along the whole 200-scan log (odometry of the laser between
// consecutive scans, as `glassmap localize` forms it), so the time per update does not depend on
// how many iterations the library chose, and a filter that loses the robot is reported
// (max_error_m, final_error_m) instead of silently measuring a lost cloud's cost.
//
//   build/tools/bench_localize [--benchmark_filter=...]
// The figure is "s/update" (wall time per update, printed with SI prefixes: 5.2m = 5.2 ms; equal
// to the CPU time on one thread on an idle machine); on a loaded machine quote the CPU column
// divided by "updates/iteration" (one thread: the main thread does all the work).
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <memory>

#include "glassmap/localize/localizer.hpp"
#include "glassmap/sim/simulator.hpp"

namespace {

using namespace glassmap;

struct Fixture {
  sim::Scene scene;
  sim::SimResult sim;
  std::vector<Pose2> laser_odom;  // odometry of the laser per scan
  Fixture() {
    scene = sim::loadScene(std::string(GLASSMAP_SOURCE_DIR) + "/maps/office-floor/scene.yaml");
    sim::SimOptions o;
    o.seed = 1;
    o.duration_limit = 20.0;  // 200 scans along the main corridor, glass on the way
    sim = sim::simulate(scene, o);
    for (const LaserScan& s : sim.log.scans) laser_odom.push_back(s.odom_pose * scene.laser.T_base_laser);
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
  std::vector<sensor::BeamSet> sets;
  for (const LaserScan& s : f.sim.log.scans) sets.push_back(sensor::makeBeamSet(s, beams));
  const std::size_t n = sets.size();
  double final_error = 0.0, max_error = 0.0;
  for (auto _ : state) {
    state.PauseTiming();
    auto filter = std::make_unique<localize::ParticleFilter>(*model, fo);
    filter->initialize(f.sim.ground_truth.front().pose, 0.1, deg2rad(3));
    state.ResumeTiming();
    filter->correct(sets[0]);
    for (std::size_t k = 1; k < n; ++k) {
      filter->predict(localize::odometryDelta(f.laser_odom[k - 1], f.laser_odom[k]));
      filter->correct(sets[k]);
      if (k % 20 == 0 || k + 1 == n) {  // the estimate (not timed: it is not part of an update)
        state.PauseTiming();
        // ground_truth holds the true laser pose of each scan (the estimate is the laser pose too).
        const double e = (filter->estimate().t - f.sim.ground_truth[k].pose.t).norm();
        max_error = std::max(max_error, e);
        final_error = e;
        state.ResumeTiming();
      }
    }
  }
  const double updates = static_cast<double>(state.iterations()) * static_cast<double>(n);
  state.counters["final_error_m"] = final_error;  // printed with SI prefixes: 4.6m = 4.6 mm
  state.counters["max_error_m"] = max_error;
  state.counters["updates/s"] = benchmark::Counter(updates, benchmark::Counter::kIsRate);
  // Seconds per update (printed with SI prefixes: 5.2m = 5.2 ms).
  state.counters["s/update"] = benchmark::Counter(updates, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  // Updates per iteration: the CPU time column over this is the CPU time per update (the figure
  // to quote on a loaded machine; on one thread it is the update's whole cost).
  state.counters["updates/iteration"] = static_cast<double>(n);
  state.counters["beam evals/s"] =
      benchmark::Counter(updates * particles * static_cast<double>(sets[0].size()), benchmark::Counter::kIsRate);
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
