// RayCaster::castBatch (SIMD lanes) against the single casts, bit for bit, on every instruction
// set this CPU runs (the scalar path always; AVX2 and AVX-512 where present).
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>
#include <random>

#include "geojson_segments.hpp"
#include "glassmap/core/angles.hpp"
#include "glassmap/geometry/ray_caster.hpp"
#include "ray_test_maps.hpp"
#include "test_data.hpp"

using namespace glassmap;

namespace {

std::vector<RayIsa> isas() {
  std::vector<RayIsa> out{RayIsa::Scalar};
  for (RayIsa isa : {RayIsa::Avx2, RayIsa::Avx512})
    if (RayCaster::isaAvailable(isa)) out.push_back(isa);
  return out;
}

struct Batch {
  std::vector<double> ox, oy, ux, uy, max_range;
  std::vector<std::int32_t> skip;
  void add(const Vec2& o, const Vec2& d, double m, std::int32_t s) {
    ox.push_back(o.x());
    oy.push_back(o.y());
    ux.push_back(d.x());
    uy.push_back(d.y());
    max_range.push_back(m);
    skip.push_back(s);
  }
  RayBatch view(bool per_ray_range, bool with_skip) const {
    RayBatch b;
    b.ox = ox.data();
    b.oy = oy.data();
    b.ux = ux.data();
    b.uy = uy.data();
    b.max_range = per_ray_range ? max_range.data() : nullptr;
    b.range = 25.0;
    b.skip = with_skip ? skip.data() : nullptr;
    b.size = ox.size();
    return b;
  }
};

// Every ray of `batch` through castBatch on every instruction set, in the four input layouts,
// against castSurface: the same range bits and segment.
void expectBatchEqualsSingleCasts(const RayCaster& caster, const Batch& batch) {
  const std::size_t n = batch.ox.size();
  for (RayIsa isa : isas()) {
    for (int layout = 0; layout < 4; ++layout) {
      const bool per_ray = layout & 1, with_skip = layout & 2;
      std::vector<double> range(n, -1.0);
      std::vector<std::int32_t> segment(n, -7);
      caster.castBatch(batch.view(per_ray, with_skip), range.data(), segment.data(), isa);
      for (std::size_t i = 0; i < n; ++i) {
        const Vec2 o(batch.ox[i], batch.oy[i]), d(batch.ux[i], batch.uy[i]);
        const double m = per_ray ? batch.max_range[i] : 25.0;
        const std::int32_t skip = with_skip ? batch.skip[i] : -1;
        const RayHit h = caster.castSurface(o, d, m, skip);
        ASSERT_EQ(segment[i], h.segment) << RayCaster::isaName(isa) << " layout " << layout << " ray " << i;
        ASSERT_EQ(std::bit_cast<std::uint64_t>(range[i]), std::bit_cast<std::uint64_t>(h.range))
            << RayCaster::isaName(isa) << " layout " << layout << " ray " << i << ": " << range[i] << " vs " << h.range;
      }
      // Without the segment output the ranges are the same.
      std::vector<double> only(n, -1.0);
      caster.castBatch(batch.view(per_ray, with_skip), only.data(), nullptr, isa);
      for (std::size_t i = 0; i < n; ++i)
        ASSERT_EQ(std::bit_cast<std::uint64_t>(only[i]), std::bit_cast<std::uint64_t>(range[i]));
    }
  }
}

Batch batchOf(const std::vector<test::RayCase>& cases) {
  Batch b;
  for (const auto& c : cases) b.add(c.origin, c.dir, c.max_range, c.skip);
  return b;
}

}  // namespace

TEST(RayBatch, ReportsTheInstructionSets) {
  EXPECT_TRUE(RayCaster::isaAvailable(RayIsa::Scalar));
  EXPECT_TRUE(RayCaster::isaAvailable(RayCaster::bestIsa()));
  std::printf("castBatch instruction sets here:");
  for (RayIsa isa : isas()) std::printf(" %s", RayCaster::isaName(isa));
  std::printf(" (auto: %s)\n", RayCaster::isaName(RayCaster::bestIsa()));
}

TEST(RayBatch, EqualsSingleCastsOnRandomMaps) {
  std::mt19937 rng(17);
  for (int m = 0; m < 6; ++m) {
    const VectorMap map = test::randomMap(rng, 40 + 80 * m);
    for (double cell : {0.0, 0.37, 1.0, 5.0}) {
      const RayCaster caster(map, {cell});
      expectBatchEqualsSingleCasts(caster, batchOf(test::rayCases(map, rng, 1500)));
      if (HasFatalFailure()) return;
    }
  }
}

TEST(RayBatch, EqualsSingleCastsOnOfficeFloor) {
  const auto path = test::sharedData("bench/office-100m.geojson");
  GLASSMAP_REQUIRE_SHARED_DATA(path);
  const VectorMap map = test::readGeoJsonSegments(path.string());
  std::mt19937 rng(23);
  const RayCaster caster(map);
  expectBatchEqualsSingleCasts(caster, batchOf(test::rayCases(map, rng, 40000)));
}

// Small batches (fewer rays than lanes, and not a multiple of them), non-finite input, zero and
// negative max range, a zero direction, and an empty map.
TEST(RayBatch, SmallAndDegenerateBatches) {
  std::mt19937 rng(29);
  const VectorMap map = test::randomMap(rng, 120);
  const RayCaster caster(map);
  const auto cases = test::rayCases(map, rng, 40);
  for (std::size_t n : {0u, 1u, 2u, 3u, 5u, 7u, 9u, 13u, 17u}) {
    Batch b;
    for (std::size_t i = 0; i < n; ++i) b.add(cases[i].origin, cases[i].dir, cases[i].max_range, cases[i].skip);
    expectBatchEqualsSingleCasts(caster, b);
  }
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  Batch odd;
  odd.add(Vec2(nan, 0), Vec2(1, 0), 10, -1);
  odd.add(Vec2(0, 0), Vec2(nan, 0), 10, -1);
  odd.add(Vec2(0, 0), Vec2(1, 0), nan, -1);
  odd.add(Vec2(0, 0), Vec2(1, 0), 0.0, -1);
  odd.add(Vec2(0, 0), Vec2(1, 0), -3.0, -1);
  odd.add(Vec2(0, 0), Vec2(0, 0), 10, -1);
  odd.add(Vec2(inf, 0), Vec2(-1, 0), 10, -1);
  odd.add(Vec2(-1e6, 0.5), Vec2(1, 0), inf, -1);
  odd.add(Vec2(0, 1e6), Vec2(0, -1), 2e6, 3);
  odd.add(Vec2(0.5, 0.5), Vec2(1, 0), inf, -1);
  for (int k = 0; k < 3; ++k)
    for (std::size_t i = 0; i < 10; ++i)  // the odd ones between ordinary rays
      odd.add(cases[i].origin, cases[i].dir, cases[i].max_range, cases[i].skip);
  expectBatchEqualsSingleCasts(caster, odd);
  const RayCaster none(VectorMap{});
  expectBatchEqualsSingleCasts(none, odd);
}

// castGroups: coherent groups (one beam from a cloud of particles, as a particle filter casts
// them; mirrored-like rays from points on a segment) and incoherent ones, against the single casts.
TEST(RayBatch, GroupsEqualSingleCasts) {
  std::mt19937 rng(31);
  std::normal_distribution<double> n01(0.0, 1.0);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::size_t hits = 0, rays = 0;
  for (int m = 0; m < 4; ++m) {
    const VectorMap map = test::randomMap(rng, 60 + 90 * m);
    for (double cell : {0.0, 0.37, 2.0}) {
      const RayCaster caster(map, {cell});
      const Eigen::AlignedBox2d box = map.bounds();
      Batch b;
      std::vector<std::size_t> ends;
      for (int group = 0; group < 60; ++group) {
        // A cloud: centre inside the bounds, spread 0.02-1 m, heading spread 0-15 deg (some
        // groups wider than the coherent limit on purpose), 1-80 rays, one beam angle.
        const Vec2 c(box.min().x() + u01(rng) * box.sizes().x(), box.min().y() + u01(rng) * box.sizes().y());
        const double spread = 0.02 + u01(rng), heading = kPi * (2 * u01(rng) - 1), beam = kPi * (2 * u01(rng) - 1);
        const double dtheta = deg2rad(group % 7 == 0 ? 40.0 : 15.0 * u01(rng));
        const int count = 1 + static_cast<int>(rng() % 80);
        const double max_range = group % 5 == 0 ? std::numeric_limits<double>::infinity() : 3.0 + 30.0 * u01(rng);
        const auto skip = group % 3 == 0 && !map.segments.empty() ? static_cast<std::int32_t>(rng() % map.segments.size())
                                                                  : -1;
        for (int k = 0; k < count; ++k) {
          const double a = heading + beam + dtheta * n01(rng);
          b.add(c + spread * Vec2(n01(rng), n01(rng)), Vec2(std::cos(a), std::sin(a)), max_range, skip);
        }
        ends.push_back(b.ox.size());
      }
      for (bool per_ray : {false, true}) {
        const RayBatch view = b.view(per_ray, true);
        std::vector<double> range(view.size, -1.0);
        std::vector<std::int32_t> segment(view.size, -7);
        caster.castGroups(view, ends.data(), ends.size(), range.data(), segment.data());
        for (std::size_t i = 0; i < view.size; ++i) {
          const double mr = per_ray ? b.max_range[i] : 25.0;
          const RayHit h = caster.castSurface(Vec2(b.ox[i], b.oy[i]), Vec2(b.ux[i], b.uy[i]), mr, b.skip[i]);
          ASSERT_EQ(segment[i], h.segment) << "map " << m << " cell " << cell << " ray " << i;
          ASSERT_EQ(std::bit_cast<std::uint64_t>(range[i]), std::bit_cast<std::uint64_t>(h.range)) << "ray " << i;
          hits += h.hit();
          ++rays;
        }
      }
    }
  }
  EXPECT_GT(hits, rays / 10);  // the comparison is not vacuous
}

TEST(RayBatch, GroupsOnOfficeFloorParticleClouds) {
  const auto path = test::sharedData("bench/office-100m.geojson");
  GLASSMAP_REQUIRE_SHARED_DATA(path);
  const VectorMap map = test::readGeoJsonSegments(path.string());
  const RayCaster caster(map);
  std::mt19937 rng(37);
  std::normal_distribution<double> n01(0.0, 1.0);
  Batch b;
  std::vector<std::size_t> ends;
  const auto cases = test::rayCases(map, rng, 200);
  for (const auto& c : cases) {  // a cloud of 64 particles around each case's origin, 61 beams
    for (int beam = 0; beam < 61; beam += 6) {
      const double a0 = std::atan2(c.dir.y(), c.dir.x()) + beam * 0.0785;
      for (int k = 0; k < 64; ++k) {
        const double a = a0 + deg2rad(2.0) * n01(rng);
        b.add(c.origin + 0.1 * Vec2(n01(rng), n01(rng)), Vec2(std::cos(a), std::sin(a)), 25.0, -1);
      }
      ends.push_back(b.ox.size());
    }
  }
  const RayBatch view = b.view(false, false);
  std::vector<double> range(view.size);
  std::vector<std::int32_t> segment(view.size);
  caster.castGroups(view, ends.data(), ends.size(), range.data(), segment.data());
  for (std::size_t i = 0; i < view.size; ++i) {
    const RayHit h = caster.castSurface(Vec2(b.ox[i], b.oy[i]), Vec2(b.ux[i], b.uy[i]), 25.0);
    ASSERT_EQ(segment[i], h.segment) << i;
    ASSERT_EQ(std::bit_cast<std::uint64_t>(range[i]), std::bit_cast<std::uint64_t>(h.range)) << i;
  }
}
