#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>

#include "geojson_segments.hpp"
#include "glassmap/core/angles.hpp"
#include "glassmap/geometry/ray_caster.hpp"

using namespace glassmap;

namespace {

MapSegment seg(double ax, double ay, double bx, double by, Material m = Material::Wall,
               double thickness = 0.1) {
  MapSegment s;
  s.a = Vec2(ax, ay);
  s.b = Vec2(bx, by);
  s.material = m;
  s.thickness = thickness;
  return s;
}

// A map that collects the awkward cases: axis-aligned and diagonal segments on a coarse lattice
// (so many share endpoints, touch in T-junctions, overlap collinearly and lie on cell borders),
// tiny, huge and zero-length segments, plus free random ones.
VectorMap randomMap(std::mt19937& rng, int count) {
  std::uniform_real_distribution<double> u(-20.0, 20.0);
  std::uniform_int_distribution<int> lattice(-10, 10);
  std::uniform_int_distribution<int> kind(0, 9);
  VectorMap map;
  for (int i = 0; i < count; ++i) {
    const int k = kind(rng);
    const Material m = (i % 3 == 0) ? Material::Glass : Material::Wall;
    if (k <= 1) {  // axis-aligned on the lattice
      const double x = lattice(rng), y = lattice(rng);
      const double len = 1 + (lattice(rng) + 10) % 6;
      map.segments.push_back(k == 0 ? seg(x, y, x + len, y, m) : seg(x, y, x, y + len, m));
    } else if (k == 2) {  // diagonal on the lattice
      const double x = lattice(rng), y = lattice(rng), len = 1 + (lattice(rng) + 10) % 4;
      map.segments.push_back(seg(x, y, x + len, y + ((i % 2) ? len : -len), m));
    } else if (k == 3) {  // tiny
      const double x = u(rng), y = u(rng);
      map.segments.push_back(seg(x, y, x + 1e-6 * u(rng), y + 1e-6 * u(rng), m));
    } else if (k == 4 && i % 7 == 0) {  // huge
      map.segments.push_back(seg(u(rng) * 50, u(rng) * 50, u(rng) * 50, u(rng) * 50, m));
    } else if (k == 5 && i % 5 == 0) {  // zero length
      const double x = lattice(rng), y = lattice(rng);
      map.segments.push_back(seg(x, y, x, y, m));
    } else if (k == 6 && !map.segments.empty()) {  // collinear continuation of another segment
      const MapSegment& o = map.segments[rng() % map.segments.size()];
      map.segments.push_back(seg(o.b.x(), o.b.y(), 2 * o.b.x() - o.a.x(), 2 * o.b.y() - o.a.y(), m));
    } else {
      map.segments.push_back(seg(u(rng), u(rng), u(rng), u(rng), m));
    }
  }
  return map;
}

void expectSameHit(const RayHit& grid, const RayHit& brute, const std::string& what) {
  ASSERT_EQ(grid.segment, brute.segment) << what;
  if (brute.hit()) {
    EXPECT_NEAR(grid.range, brute.range, 1e-9) << what;
    EXPECT_EQ(grid.material, brute.material) << what;
    EXPECT_NEAR(grid.incidence, brute.incidence, 1e-12) << what;
  } else {
    EXPECT_TRUE(std::isinf(grid.range)) << what;
  }
}

std::string describe(const Vec2& o, const Vec2& d, double max_range, int skip) {
  char buf[200];
  std::snprintf(buf, sizeof buf, "origin (%.17g, %.17g) dir (%.17g, %.17g) max %.17g skip %d",
                o.x(), o.y(), d.x(), d.y(), max_range, skip);
  return buf;
}

// Casts many rays of every kind against `caster` and compares with brute force.
void compareWithBruteForce(const RayCaster& caster, std::mt19937& rng, int rays) {
  const Box2 box = caster.map().bounds();
  const Vec2 size = box.max - box.min;
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::uniform_real_distribution<double> angle(-kPi, kPi);
  const auto& segs = caster.map().segments;
  const double extent = std::max(size.x(), size.y());
  int hits = 0;
  for (int i = 0; i < rays; ++i) {
    const int kind = i % 8;
    // Origins: mostly inside the bounds, some outside, some exactly on a segment or endpoint.
    Vec2 o(box.min.x() + (uni(rng) * 1.4 - 0.2) * size.x(),
           box.min.y() + (uni(rng) * 1.4 - 0.2) * size.y());
    int skip = -1;
    if (kind == 1 && !segs.empty()) {
      const auto id = static_cast<int>(rng() % segs.size());
      o = segs[id].a + uni(rng) * (segs[id].b - segs[id].a);
      if (i % 16 == 1) skip = id;
    } else if (kind == 2 && !segs.empty()) {
      o = segs[rng() % segs.size()].b;  // on an endpoint
    } else if (kind == 3) {
      o = Vec2(std::round(o.x()), std::round(o.y()));  // on the lattice, often on cell borders
    }
    Vec2 d(std::cos(angle(rng)), std::sin(angle(rng)));
    d.normalize();
    if (kind == 3 || kind == 4) {  // axis-aligned and diagonal
      const int q = static_cast<int>(rng() % 8);
      d = Vec2(std::cos(q * kPi / 4), std::sin(q * kPi / 4));
      if (q % 2 == 0) d = Vec2(std::round(d.x()), std::round(d.y()));
    } else if (kind == 5 && !segs.empty()) {  // aimed at an endpoint
      const MapSegment& s = segs[rng() % segs.size()];
      const Vec2 target = (rng() % 2) ? s.a : s.b;
      if ((target - o).norm() > 1e-9) d = (target - o).normalized();
    }
    double max_range = (0.05 + uni(rng)) * extent;
    if (i % 11 == 0) max_range = std::numeric_limits<double>::infinity();
    if (i % 13 == 0) max_range = 1e-3;
    const RayHit g = caster.cast(o, d, max_range, skip);
    const RayHit b = caster.castBruteForce(o, d, max_range, skip);
    expectSameHit(g, b, describe(o, d, max_range, skip));
    if (::testing::Test::HasFatalFailure()) return;
    hits += b.hit();
    EXPECT_EQ(caster.castRange(o, d, max_range, skip), g.range);
  }
  EXPECT_GT(hits, rays / 10);  // the comparison is not vacuous
}

}  // namespace

TEST(RayCaster, MatchesBruteForceOnRandomMaps) {
  std::mt19937 rng(7);
  for (int m = 0; m < 8; ++m) {
    const VectorMap map = randomMap(rng, 40 + 60 * m);
    for (double cell : {0.0, 0.37, 1.0, 5.0}) {
      const RayCaster caster(map, {cell});
      compareWithBruteForce(caster, rng, 4000);
      if (HasFatalFailure()) return;
    }
  }
}

TEST(RayCaster, MatchesBruteForceOnOfficeFloor) {
  const std::string path = GLASSMAP_SOURCE_DIR "/../shared/data/bench/office-100m.geojson";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "no " << path;
  const VectorMap map = test::readGeoJsonSegments(path);
  ASSERT_EQ(map.segments.size(), 2266u);
  std::mt19937 rng(11);
  const RayCaster caster(map);
  compareWithBruteForce(caster, rng, 60000);
  const RayCaster fine(map, {0.25});
  compareWithBruteForce(fine, rng, 10000);
}

TEST(RayCaster, KnownHitsRangeAndIncidence) {
  VectorMap map;
  map.segments.push_back(seg(5, -5, 5, 5, Material::Glass));  // x = 5
  map.segments.push_back(seg(10, -10, 10, 10));                // x = 10
  const RayCaster caster(map);
  RayHit h = caster.cast(Vec2(0, 0), 0.0, 30.0);
  ASSERT_TRUE(h.hit());
  EXPECT_EQ(h.segment, 0);
  EXPECT_EQ(h.material, Material::Glass);
  EXPECT_NEAR(h.range, 5.0, 1e-12);
  EXPECT_NEAR(h.incidence, 0.0, 1e-12);
  // 30 degrees off the normal, both ways, and from the other side.
  h = caster.cast(Vec2(0, 0), kPi / 6, 30.0);
  EXPECT_NEAR(h.range, 5.0 / std::cos(kPi / 6), 1e-12);
  EXPECT_NEAR(h.incidence, kPi / 6, 1e-12);
  h = caster.cast(Vec2(0, 0), -kPi / 6, 30.0);
  EXPECT_NEAR(h.incidence, kPi / 6, 1e-12);
  h = caster.cast(Vec2(7, 0), kPi - kPi / 3, 30.0);
  EXPECT_EQ(h.segment, 0);
  EXPECT_NEAR(h.incidence, kPi / 3, 1e-12);
  EXPECT_NEAR(h.range, 2.0 / std::cos(kPi / 3), 1e-12);
  // Skip the pane: the wall behind it.
  h = caster.cast(Vec2(0, 0), 0.0, 30.0, 0);
  EXPECT_EQ(h.segment, 1);
  EXPECT_NEAR(h.range, 10.0, 1e-12);
  // Starting on the pane: the pane itself is not hit (s > 0), with or without skip.
  h = caster.cast(Vec2(5, 1), 0.0, 30.0);
  EXPECT_EQ(h.segment, 1);
  EXPECT_NEAR(h.range, 5.0, 1e-12);
  // Max range short of the pane, exactly at it, and away from everything.
  EXPECT_FALSE(caster.cast(Vec2(0, 0), 0.0, 4.999).hit());
  EXPECT_TRUE(caster.cast(Vec2(0, 0), 0.0, 5.0).hit());
  EXPECT_FALSE(caster.cast(Vec2(0, 0), kPi, 1e6).hit());
  // Parallel and collinear rays do not hit.
  EXPECT_FALSE(caster.cast(Vec2(5, -8), kPi / 2, 3.0).hit());
  EXPECT_EQ(caster.cast(Vec2(5, -8), kPi / 2, 30.0).segment, -1);
}

TEST(RayCaster, RaysFromOutsideTheGridAndBeyondIt) {
  VectorMap map;
  map.segments.push_back(seg(0, 0, 0, 2));
  map.segments.push_back(seg(3, 0, 3, 2));
  const RayCaster caster(map);
  RayHit h = caster.cast(Vec2(-100, 1), 0.0, 1000.0);
  EXPECT_EQ(h.segment, 0);
  EXPECT_NEAR(h.range, 100.0, 1e-12);
  h = caster.cast(Vec2(1000, 1), kPi, std::numeric_limits<double>::infinity());
  EXPECT_EQ(h.segment, 1);
  EXPECT_NEAR(h.range, 997.0, 1e-9);
  EXPECT_FALSE(caster.cast(Vec2(-100, 5), 0.0, 1000.0).hit());  // passes above the grid
  EXPECT_FALSE(caster.cast(Vec2(-100, 1), 0.0, 99.0).hit());    // ends before it
  // Endpoint hits (a corner) count.
  h = caster.cast(Vec2(-1, 2), Vec2(1, 0), 10.0);
  EXPECT_EQ(h.segment, 0);
  EXPECT_EQ(h.range, 1.0);
  EXPECT_EQ(caster.cast(Vec2(3.5, 0), Vec2(-1, 0), 10.0).segment, 1);
}

TEST(RayCaster, DegenerateMaps) {
  VectorMap empty;
  const RayCaster none(empty);
  EXPECT_FALSE(none.cast(Vec2(0, 0), 0.3, 10.0).hit());
  VectorMap points;
  points.segments.push_back(seg(1, 0, 1, 0));
  const RayCaster dots(points);
  EXPECT_FALSE(dots.cast(Vec2(0, 0), 0.0, 10.0).hit());
  EXPECT_FALSE(dots.castBruteForce(Vec2(0, 0), 0.0, 10.0).hit());
  points.segments.push_back(seg(2, -1, 2, 1));
  const RayCaster one(points);
  EXPECT_EQ(one.cast(Vec2(0, 0), 0.0, 10.0).segment, 1);
}

TEST(RayCaster, TiesGoToTheLowerSegmentId) {
  VectorMap map;
  map.segments.push_back(seg(2, 0, 2, 2));  // both meet at (2, 0)
  map.segments.push_back(seg(2, 0, 4, -2));
  map.segments.push_back(seg(2, 0, 0, -2));
  const RayCaster caster(map, {0.5});
  const RayHit h = caster.cast(Vec2(0, 0), 0.0, 10.0);
  EXPECT_EQ(h.segment, 0);
  EXPECT_NEAR(h.range, 2.0, 1e-12);
  EXPECT_EQ(caster.cast(Vec2(0, 0), 0.0, 10.0, 0).segment, 1);
}

TEST(RayCaster, ScanMatchesSingleCasts) {
  std::mt19937 rng(3);
  const VectorMap map = randomMap(rng, 200);
  const RayCaster caster(map);
  std::vector<double> ranges(61);
  const double start = -0.75 * kPi, step = 1.5 * kPi / 60;
  caster.castScan(Vec2(0.5, 0.5), start, step, 61, 30.0, ranges.data());
  for (int k = 0; k < 61; ++k) {
    const RayHit h = caster.cast(Vec2(0.5, 0.5), start + k * step, 30.0);
    EXPECT_NEAR(ranges[k], h.hit() ? h.range : 30.0, 1e-9) << k;
  }
}
