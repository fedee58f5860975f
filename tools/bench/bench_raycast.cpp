// Ray casting against the office-100m floor (2,266 segments), the query set of
// ../shared/data/bench/README.md: 2,500 poses uniformly in free space (not within 0.2 m of a
// segment, inside the floor), 61 beams over 270 degrees, 25 m max range. Reports rays/s.
//
//   build-geo/tools/bench_raycast [--benchmark_filter=...]
// Environment: GLASSMAP_BENCH_MAP overrides the floorplan path (any format readFloorplan reads).

#include <benchmark/benchmark.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "glassmap/core/angles.hpp"
#include "glassmap/geometry/ray_caster.hpp"
#include "glassmap/io/floorplan.hpp"

using namespace glassmap;

namespace {

constexpr int kPoses = 2500;
constexpr int kBeams = 61;
constexpr double kFov = 1.5 * kPi;  // 270 degrees
constexpr double kMaxRange = 25.0;
constexpr double kClearance = 0.2;

VectorMap loadMap() {
  const char* env = std::getenv("GLASSMAP_BENCH_MAP");
  return readFloorplan(env ? env : GLASSMAP_SOURCE_DIR "/../shared/data/bench/office-100m.geojson");
}

struct Query {
  VectorMap map;
  RayCaster caster;
  std::vector<Pose2> poses;
  std::vector<Vec2> beam_dirs;  // laser-frame unit directions
};

Query& query() {
  static Query q = [] {
    VectorMap map = loadMap();
    RayCaster caster(map);
    const Eigen::AlignedBox2d box = map.bounds();
    std::mt19937 rng(42);
    std::uniform_real_distribution<double> ux(box.min().x(), box.max().x()), uy(box.min().y(), box.max().y());
    std::uniform_real_distribution<double> heading(-kPi, kPi);
    std::vector<Pose2> poses;
    while (static_cast<int>(poses.size()) < kPoses) {
      const Vec2 p(ux(rng), uy(rng));
      bool free = true;
      for (const auto& s : map.segments) {
        if (s.distanceTo(p) < kClearance) {
          free = false;
          break;
        }
      }
      // Inside the floor: enclosed in all four axis directions.
      for (int k = 0; free && k < 4; ++k) {
        free = caster.cast(p, k * kPi / 2, 1e9).hit();
      }
      if (free) poses.emplace_back(p, heading(rng));
    }
    std::vector<Vec2> dirs;
    for (int k = 0; k < kBeams; ++k) {
      const double a = -kFov / 2 + k * kFov / (kBeams - 1);
      dirs.emplace_back(std::cos(a), std::sin(a));
    }
    return Query{std::move(map), std::move(caster), std::move(poses), std::move(dirs)};
  }();
  return q;
}

// Casts all beams of poses [begin, end) with `caster`; returns a checksum of the ranges.
double castPoses(const RayCaster& caster, const Query& q, int begin, int end) {
  double sum = 0.0;
  for (int i = begin; i < end; ++i) {
    const Pose2& pose = q.poses[static_cast<std::size_t>(i)];
    const double c = std::cos(pose.theta), s = std::sin(pose.theta);
    for (const Vec2& b : q.beam_dirs) {
      const Vec2 dir(c * b.x() - s * b.y(), s * b.x() + c * b.y());
      const double r = caster.castRange(pose.t, dir, kMaxRange);
      sum += std::isinf(r) ? kMaxRange : r;
    }
  }
  return sum;
}

void BM_BuildIndex(benchmark::State& state) {
  const Query& q = query();
  for (auto _ : state) {
    RayCaster caster(q.map);
    benchmark::DoNotOptimize(caster.cellEntries());
  }
  state.counters["cell_m"] = q.caster.cellSize();
  state.counters["cells"] = static_cast<double>(q.caster.cellsX()) * q.caster.cellsY();
  state.counters["entries"] = static_cast<double>(q.caster.cellEntries());
}
BENCHMARK(BM_BuildIndex)->Unit(benchmark::kMillisecond);

// The main figure: grid DDA, one thread, castRange with precomputed beam directions.
void BM_GridRange(benchmark::State& state) {
  const Query& q = query();
  for (auto _ : state) benchmark::DoNotOptimize(castPoses(q.caster, q, 0, kPoses));
  state.SetItemsProcessed(state.iterations() * kPoses * kBeams);
  state.counters["cell_m"] = q.caster.cellSize();
}
BENCHMARK(BM_GridRange)->Unit(benchmark::kMillisecond);

// castBatch (SIMD lanes, one ray each) over all 2,500 x 61 rays, 64 poses per batch; filling the
// batch's arrays (origin and rotated beam direction per ray) is timed too. Argument: RayIsa
// (1 scalar, 2 AVX2, 3 AVX-512).
// Fills the batch arrays for poses [p0, p0 + n) x all beams and casts them with castBatch;
// returns the checksum of the ranges.
double batchPoses(const Query& q, int p0, int n, RayIsa isa, std::vector<double>* buf) {
  std::vector<double>& ox = buf[0];
  std::vector<double>& oy = buf[1];
  std::vector<double>& ux = buf[2];
  std::vector<double>& uy = buf[3];
  std::vector<double>& range = buf[4];
  for (int k = 0; k < 5; ++k) buf[k].resize(static_cast<std::size_t>(n) * kBeams);
  std::size_t k = 0;
  for (int i = p0; i < p0 + n; ++i) {
    const Pose2& pose = q.poses[static_cast<std::size_t>(i)];
    const double c = std::cos(pose.theta), s = std::sin(pose.theta);
    for (const Vec2& b : q.beam_dirs) {
      ox[k] = pose.t.x();
      oy[k] = pose.t.y();
      ux[k] = c * b.x() - s * b.y();
      uy[k] = s * b.x() + c * b.y();
      ++k;
    }
  }
  RayBatch batch;
  batch.ox = ox.data();
  batch.oy = oy.data();
  batch.ux = ux.data();
  batch.uy = uy.data();
  batch.range = kMaxRange;
  batch.size = k;
  q.caster.castBatch(batch, range.data(), nullptr, isa);
  double sum = 0.0;
  for (std::size_t j = 0; j < k; ++j) sum += std::isinf(range[j]) ? kMaxRange : range[j];
  return sum;
}

constexpr int kBatchPoses = 64;  // poses per castBatch call

void BM_BatchRange(benchmark::State& state) {
  const Query& q = query();
  const auto isa = static_cast<RayIsa>(state.range(0));
  if (!RayCaster::isaAvailable(isa)) {
    state.SkipWithError("the CPU lacks this instruction set");
    return;
  }
  std::vector<double> buf[5];
  for (auto _ : state) {
    double sum = 0.0;
    for (int p0 = 0; p0 < kPoses; p0 += kBatchPoses)
      sum += batchPoses(q, p0, std::min(kBatchPoses, kPoses - p0), isa, buf);
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * kPoses * kBeams);
  state.SetLabel(RayCaster::isaName(isa));
}
BENCHMARK(BM_BatchRange)
    ->Arg(static_cast<int>(RayIsa::Scalar))
    ->Arg(static_cast<int>(RayIsa::Avx2))
    ->Arg(static_cast<int>(RayIsa::Avx512))
    ->Unit(benchmark::kMillisecond);

// A particle filter's rays: at 100 of the query poses a cloud of 256 particles (0.1 m, 1 deg), all
// 61 beams from each, beam-major (one beam of one cloud is a coherent group). Argument 0: castBatch
// (each ray its own SIMD lane); 1: castGroups (a group shares one sweep of the grid).
void BM_Clouds(benchmark::State& state) {
  const Query& q = query();
  constexpr int kClouds = 100, kParticles = 256;
  static std::vector<double> ox, oy, ux, uy;
  static std::vector<std::size_t> ends;
  if (ox.empty()) {
    std::mt19937 rng(3);
    std::normal_distribution<double> n01(0.0, 1.0);
    for (int c = 0; c < kClouds; ++c) {
      const Pose2& pose = q.poses[static_cast<std::size_t>(c)];
      std::vector<Pose2> cloud;
      for (int j = 0; j < kParticles; ++j)
        cloud.emplace_back(pose.t + 0.1 * Vec2(n01(rng), n01(rng)), pose.theta + deg2rad(1.0) * n01(rng));
      for (const Vec2& b : q.beam_dirs) {
        for (const Pose2& p : cloud) {
          const double cs = std::cos(p.theta), sn = std::sin(p.theta);
          ox.push_back(p.t.x());
          oy.push_back(p.t.y());
          ux.push_back(cs * b.x() - sn * b.y());
          uy.push_back(sn * b.x() + cs * b.y());
        }
        ends.push_back(ox.size());
      }
    }
  }
  RayBatch batch;
  batch.ox = ox.data();
  batch.oy = oy.data();
  batch.ux = ux.data();
  batch.uy = uy.data();
  batch.range = kMaxRange;
  batch.size = ox.size();
  std::vector<double> range(ox.size());
  for (auto _ : state) {
    if (state.range(0) == 0)
      q.caster.castBatch(batch, range.data());
    else
      q.caster.castGroups(batch, ends.data(), ends.size(), range.data());
    benchmark::DoNotOptimize(range.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(ox.size()));
  state.SetLabel(state.range(0) == 0 ? "castBatch" : "castGroups");
}
BENCHMARK(BM_Clouds)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// Full RayHit (segment, material, incidence angle) with precomputed beam directions.
void BM_GridCastDir(benchmark::State& state) {
  const Query& q = query();
  for (auto _ : state) {
    double sum = 0.0;
    for (const Pose2& pose : q.poses) {
      const double c = std::cos(pose.theta), s = std::sin(pose.theta);
      for (const Vec2& b : q.beam_dirs) {
        const Vec2 dir(c * b.x() - s * b.y(), s * b.x() + c * b.y());
        const RayHit h = q.caster.cast(pose.t, dir, kMaxRange);
        sum += h.hit() ? h.range + h.incidence : kMaxRange;
      }
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * kPoses * kBeams);
}
BENCHMARK(BM_GridCastDir)->Unit(benchmark::kMillisecond);

// Full RayHit with sin/cos per beam (cast(origin, angle, ...)): what a naive caller pays.
void BM_GridCastAngle(benchmark::State& state) {
  const Query& q = query();
  for (auto _ : state) {
    double sum = 0.0;
    for (const Pose2& pose : q.poses) {
      for (int k = 0; k < kBeams; ++k) {
        const double a = pose.theta - kFov / 2 + k * kFov / (kBeams - 1);
        const RayHit h = q.caster.cast(pose.t, a, kMaxRange);
        sum += h.hit() ? h.range + h.incidence : kMaxRange;
      }
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * kPoses * kBeams);
}
BENCHMARK(BM_GridCastAngle)->Unit(benchmark::kMillisecond);

// castScan: one sin/cos per scan, directions by rotation recurrence.
void BM_GridScan(benchmark::State& state) {
  const Query& q = query();
  std::vector<double> ranges(kBeams);
  for (auto _ : state) {
    for (const Pose2& pose : q.poses) {
      q.caster.castScan(pose.t, pose.theta - kFov / 2, kFov / (kBeams - 1), kBeams, kMaxRange, ranges.data());
      benchmark::DoNotOptimize(ranges.data());
    }
  }
  state.SetItemsProcessed(state.iterations() * kPoses * kBeams);
}
BENCHMARK(BM_GridScan)->Unit(benchmark::kMillisecond);

// Cell size sweep [cm]; 0 = automatic.
void BM_GridCellSize(benchmark::State& state) {
  const Query& q = query();
  const RayCaster caster(q.map, {static_cast<double>(state.range(0)) / 100.0});
  for (auto _ : state) benchmark::DoNotOptimize(castPoses(caster, q, 0, kPoses));
  state.SetItemsProcessed(state.iterations() * kPoses * kBeams);
  state.counters["cell_m"] = caster.cellSize();
  state.counters["entries"] = static_cast<double>(caster.cellEntries());
}
BENCHMARK(BM_GridCellSize)->Arg(50)->Arg(100)->Arg(150)->Arg(200)->Arg(300)->Arg(500)->Unit(benchmark::kMillisecond);

// Brute force over all segments: the reference, on the first 100 poses.
void BM_BruteForce(benchmark::State& state) {
  const Query& q = query();
  constexpr int kSample = 100;
  for (auto _ : state) {
    double sum = 0.0;
    for (int i = 0; i < kSample; ++i) {
      const Pose2& pose = q.poses[static_cast<std::size_t>(i)];
      const double c = std::cos(pose.theta), s = std::sin(pose.theta);
      for (const Vec2& b : q.beam_dirs) {
        const Vec2 dir(c * b.x() - s * b.y(), s * b.x() + c * b.y());
        const RayHit h = q.caster.castBruteForce(pose.t, dir, kMaxRange);
        sum += h.hit() ? h.range : kMaxRange;
      }
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * kSample * kBeams);
}
BENCHMARK(BM_BruteForce)->Unit(benchmark::kMillisecond);

// castBatch (the CPU's best instruction set) on state.range(0) threads, 64 poses per task
// (wall-clock rate).
void BM_BatchParallel(benchmark::State& state) {
  const Query& q = query();
  const auto threads = static_cast<std::size_t>(state.range(0));
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  tbb::enumerable_thread_specific<std::array<std::vector<double>, 5>> bufs;
  for (auto _ : state) {
    tbb::parallel_for(tbb::blocked_range<int>(0, kPoses, kBatchPoses), [&](const tbb::blocked_range<int>& r) {
      benchmark::DoNotOptimize(batchPoses(q, r.begin(), r.size(), RayIsa::Auto, bufs.local().data()));
    });
  }
  state.SetItemsProcessed(state.iterations() * kPoses * kBeams);
  state.counters["threads"] = static_cast<double>(threads);
  state.SetLabel(RayCaster::isaName(RayCaster::bestIsa()));
}
BENCHMARK(BM_BatchParallel)->Arg(1)->Arg(2)->UseRealTime()->MeasureProcessCPUTime()->Unit(benchmark::kMillisecond);

// TBB parallel_for over poses with state.range(0) threads (wall-clock rate).
void BM_GridParallel(benchmark::State& state) {
  const Query& q = query();
  const auto threads = static_cast<std::size_t>(state.range(0));
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  for (auto _ : state) {
    tbb::parallel_for(tbb::blocked_range<int>(0, kPoses, 16), [&](const tbb::blocked_range<int>& r) {
      benchmark::DoNotOptimize(castPoses(q.caster, q, r.begin(), r.end()));
    });
  }
  state.SetItemsProcessed(state.iterations() * kPoses * kBeams);
  state.counters["threads"] = static_cast<double>(threads);
}
BENCHMARK(BM_GridParallel)
    ->Arg(1)
    ->Arg(2)
    ->Arg(4)
    ->UseRealTime()
    ->MeasureProcessCPUTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
