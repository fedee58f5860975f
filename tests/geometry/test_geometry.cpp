#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>

#include "geojson_segments.hpp"
#include "glassmap/core/angles.hpp"
#include "glassmap/geometry/optics.hpp"
#include "glassmap/geometry/ray_caster.hpp"
#include "ray_test_maps.hpp"
#include "test_data.hpp"

using namespace glassmap;
using glassmap::test::randomMap;
using glassmap::test::seg;

namespace {

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
  std::snprintf(buf, sizeof buf, "origin (%.17g, %.17g) dir (%.17g, %.17g) max %.17g skip %d", o.x(), o.y(), d.x(),
                d.y(), max_range, skip);
  return buf;
}

// Casts many rays of every kind against `caster` and compares with brute force.
void compareWithBruteForce(const RayCaster& caster, std::mt19937& rng, int rays) {
  int hits = 0;
  for (const test::RayCase& c : test::rayCases(caster.map(), rng, rays)) {
    const Vec2 &o = c.origin, &d = c.dir;
    const double max_range = c.max_range;
    const int skip = c.skip;
    const RayHit g = caster.cast(o, d, max_range, skip);
    const RayHit b = caster.castBruteForce(o, d, max_range, skip);
    expectSameHit(g, b, describe(o, d, max_range, skip));
    if (::testing::Test::HasFatalFailure()) return;
    hits += b.hit();
    EXPECT_EQ(caster.castRange(o, d, max_range, skip), g.range);
    const RayHit s = caster.castSurface(o, d, max_range, skip);
    EXPECT_EQ(s.range, g.range);
    EXPECT_EQ(s.segment, g.segment);
    if (g.hit()) {
      EXPECT_EQ(s.material, g.material);
      EXPECT_EQ(caster.incidence(g.segment, d), g.incidence);
    }
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
  const auto path = test::sharedData("bench/office-100m.geojson");
  GLASSMAP_REQUIRE_SHARED_DATA(path);
  const VectorMap map = test::readGeoJsonSegments(path.string());
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
  map.segments.push_back(seg(10, -10, 10, 10));               // x = 10
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
  // Non-finite input is a miss, not undefined behaviour.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(one.cast(Vec2(nan, 0), 0.0, 10.0).hit());
  EXPECT_FALSE(one.cast(Vec2(0, 0), Vec2(nan, 0), 10.0).hit());
  EXPECT_FALSE(one.castBruteForce(Vec2(nan, 0), 0.0, 10.0).hit());
  EXPECT_FALSE(one.cast(Vec2(0, 0), 0.0, nan).hit());
  EXPECT_FALSE(one.cast(Vec2(0, 0), 0.0, 0.0).hit());
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

// A closed polygon: no ray from inside may escape, not even one aimed exactly at a corner where
// two segments meet (the endpoint slack keeps corners watertight against rounding).
TEST(RayCaster, ClosedPolygonIsWatertight) {
  VectorMap map;
  const int n = 37;
  std::vector<Vec2> corners;
  for (int k = 0; k < n; ++k) {
    corners.emplace_back(0.3 + 5 * std::cos(2 * kPi * k / n), 0.1 + 5 * std::sin(2 * kPi * k / n));
  }
  for (int k = 0; k < n; ++k) {
    const Vec2& a = corners[k];
    const Vec2& b = corners[(k + 1) % n];
    map.segments.push_back(seg(a.x(), a.y(), b.x(), b.y()));
  }
  const RayCaster caster(map, {0.7});
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (int i = 0; i < 20000; ++i) {
    const Vec2 o(0.3 + u(rng), 0.1 + u(rng));
    const Vec2 d = (corners[static_cast<std::size_t>(i) % n] - o).normalized();
    const RayHit h = caster.cast(o, d, 100.0);
    ASSERT_TRUE(h.hit()) << describe(o, d, 100.0, -1);
    EXPECT_LT(h.range, 5.0 + 3 * std::sqrt(2.0));
    const int k = i % n;  // the corner joins segments k - 1 and k; either may report it
    EXPECT_TRUE(h.segment == k || h.segment == (k + n - 1) % n) << h.segment << " " << k;
  }
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

// ---------------------------------------------------------------------------------------------
// Optics

TEST(Optics, NormalIncidenceReflectsFourPercent) {
  const Fresnel f = fresnel(0.0, 1.0, 1.5);
  EXPECT_NEAR(f.r_s, 0.04, 1e-12);
  EXPECT_NEAR(f.r_p, 0.04, 1e-12);
  EXPECT_NEAR(f.reflectance(), 0.04, 1e-12);
  EXPECT_NEAR(f.transmittance(), 0.96, 1e-12);
  EXPECT_FALSE(f.total_internal_reflection);
  EXPECT_NEAR(reflectance(0.0, 1.5, 1.0), 0.04, 1e-12);  // same from the glass side
}

TEST(Optics, ReflectancePlusTransmittanceIsOne) {
  for (double n2 : {1.33, 1.5, 1.9}) {
    for (int k = 0; k <= 90; ++k) {
      const double th = deg2rad(k);
      const Fresnel f = fresnel(th, 1.0, n2);
      EXPECT_NEAR(f.r_s + f.t_s, 1.0, 1e-12) << k;
      EXPECT_NEAR(f.r_p + f.t_p, 1.0, 1e-12) << k;
      EXPECT_GE(f.r_s, f.r_p - 1e-15) << k;    // s reflects at least as much as p
      const Fresnel g = fresnel(th, n2, 1.0);  // from the dense side, below the critical angle
      if (!g.total_internal_reflection) {
        EXPECT_NEAR(g.r_s + g.t_s, 1.0, 1e-12) << k;
      }
    }
  }
}

TEST(Optics, GrazingIncidenceReflectsEverything) {
  EXPECT_NEAR(reflectance(kPi / 2), 1.0, 1e-12);
  EXPECT_NEAR(transmittance(kPi / 2), 0.0, 1e-12);
  EXPECT_GT(reflectance(deg2rad(89.0)), 0.9);
  // Reflectance rises monotonically from the normal to grazing (unpolarised, s).
  double last = 0.0;
  for (int k = 0; k <= 90; ++k) {
    const Fresnel f = fresnel(deg2rad(k));
    EXPECT_GE(f.r_s, last);
    last = f.r_s;
  }
  // Paper's reading of Fig. 4: at 76 degrees about 30% (unpolarised) is reflected.
  EXPECT_NEAR(reflectance(deg2rad(76.0)), 0.30, 0.05);
}

TEST(Optics, BrewsterAngleKillsPPolarisedReflection) {
  const double b = brewsterAngle(1.0, 1.5);
  EXPECT_NEAR(b, std::atan(1.5), 1e-15);
  EXPECT_NEAR(rad2deg(b), 56.31, 0.01);
  EXPECT_NEAR(fresnel(b).r_p, 0.0, 1e-15);
  EXPECT_GT(fresnel(b).r_s, 0.1);
  EXPECT_GT(fresnel(b - 0.1).r_p, 1e-4);
}

TEST(Optics, SnellAndTotalInternalReflection) {
  const auto t = refractionAngle(deg2rad(30.0), 1.0, 1.5);
  ASSERT_TRUE(t.has_value());
  EXPECT_NEAR(std::sin(*t), 0.5 / 1.5, 1e-15);
  const double c = criticalAngle(1.5, 1.0);
  EXPECT_NEAR(c, std::asin(1.0 / 1.5), 1e-15);
  EXPECT_TRUE(refractionAngle(c - 1e-9, 1.5, 1.0).has_value());
  EXPECT_FALSE(refractionAngle(c + 1e-9, 1.5, 1.0).has_value());
  const Fresnel inside = fresnel(c + 0.01, 1.5, 1.0);
  EXPECT_TRUE(inside.total_internal_reflection);
  EXPECT_EQ(inside.reflectance(), 1.0);
  EXPECT_EQ(inside.transmittance(), 0.0);
  // Just below the critical angle reflection is already strong, and reaches 1 at it.
  EXPECT_GT(fresnel(c - 1e-6, 1.5, 1.0).reflectance(), 0.95);
  EXPECT_EQ(criticalAngle(1.0, 1.5), kPi / 2);  // never from the thin side
}

TEST(Optics, ElongationGrowsWithThicknessZeroWithout) {
  EXPECT_EQ(paneRangeElongation(0.0, 0.3), 0.0);
  EXPECT_EQ(paneOpticalExcess(0.0, 0.3), 0.0);
  EXPECT_NEAR(paneRangeElongation(0.08, 0.0), 0.08 * 0.5, 1e-15);  // t (n - 1)
  EXPECT_NEAR(paneOpticalExcess(0.08, 0.0), 0.04, 1e-15);
  for (int k = 0; k < 89; k += 4) {
    const double th = deg2rad(k);
    if (th < brewsterAngle()) {
      EXPECT_GT(paneRangeElongation(0.02, th), paneRangeElongation(0.01, th)) << k;
    }
    EXPECT_NEAR(paneRangeElongation(0.02, th), 2 * paneRangeElongation(0.01, th), 1e-15) << k;
    // The excess over the real (bent) path grows with angle too ...
    EXPECT_GT(paneOpticalExcess(0.01, th + deg2rad(4)), paneOpticalExcess(0.01, th)) << k;
    // ... while the elongation over a straight map ray falls with angle (the bent path is shorter).
    EXPECT_LT(paneRangeElongation(0.01, th + deg2rad(4)), paneRangeElongation(0.01, th)) << k;
  }
  EXPECT_NEAR(paneRangeElongation(0.01, brewsterAngle()), 0.0, 1e-15);
  EXPECT_EQ(paneLateralShift(0.01, 0.0), 0.0);
  EXPECT_GT(paneLateralShift(0.01, 0.5), 0.0);
}

// A beam through a pane, traced face by face with the ray caster, reads longer than the straight
// map ray to the wall behind by exactly the elongation.
TEST(Optics, RayThroughPaneIsLongerByTheElongation) {
  const double t = 0.08, n = 1.5;
  VectorMap map;
  map.segments.push_back(seg(5, -60, 5, 60, Material::Glass, t));  // entry face x = 5
  map.segments.push_back(seg(12, -80, 12, 80));                    // wall parallel to it
  const RayCaster caster(map);
  for (int k = -80; k <= 80; k += 5) {
    const double th = deg2rad(k);
    const Vec2 dir(std::cos(th), std::sin(th));
    const RayHit pane = caster.cast(Vec2(0, 0), dir, 100.0);
    ASSERT_EQ(pane.segment, 0) << k;
    EXPECT_NEAR(pane.incidence, std::abs(th), 1e-12);
    const Vec2 entry = pane.range * dir;
    const PaneCrossing crossing = crossPane(entry, dir, Vec2(-1, 0), t, n);
    EXPECT_NEAR(crossing.exit.x(), 5 + t, 1e-12);
    EXPECT_NEAR(crossing.geometric_length, paneGlassPath(t, th, n), 1e-12);
    const RayHit after = caster.cast(crossing.exit, dir, 100.0, 0);
    ASSERT_EQ(after.segment, 1) << k;
    const double reported = pane.range + crossing.optical_length + after.range;
    const double d_real = caster.cast(Vec2(0, 0), dir, 100.0, 0).range;  // ignores the glass
    EXPECT_NEAR(reported - d_real, paneRangeElongation(t, th, n), 1e-12) << k;
    // Against the path the light really took the excess is (n - 1) t / cos(theta_t).
    const double real_path = pane.range + crossing.geometric_length + after.range;
    EXPECT_NEAR(reported - real_path, paneOpticalExcess(t, th, n), 1e-12) << k;
    // The exit point is shifted sideways off the straight ray by the lateral shift.
    const double off_line = std::abs(dir.x() * crossing.exit.y() - dir.y() * crossing.exit.x());
    EXPECT_NEAR(off_line, paneLateralShift(t, th, n), 1e-12) << k;
  }
}
