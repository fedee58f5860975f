// Mirror phantoms: a corridor (y = 0 .. 3) whose lower side is a glass pane along y = 0 in front of a
// room closed by a wall at y = -2. A beam that meets the pane either returns directly (near the
// normal), passes through to the room wall, or is reflected up to the corridor wall at y = 3; the
// sensor then reports the folded path as straight, which draws a phantom wall at y = -3, behind the
// real room wall. suppressMirrorPhantoms must clear the phantom and keep the real walls and the pane.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "glassmap/geometry/ray_caster.hpp"
#include "glassmap/glass/mapping.hpp"
#include "glassmap/glass/phantoms.hpp"

namespace glassmap::glass {
namespace {

VectorMap corridor() {
  VectorMap m;
  auto add = [&](Vec2 a, Vec2 b, Material mat) { m.add(a, b, mat); };
  add({-1, 3}, {13, 3}, Material::Wall);  // corridor wall
  add({0, 0}, {12, 0}, Material::Glass);  // the pane
  add({-1, 0}, {0, 0}, Material::Wall);   // pane frame
  add({12, 0}, {13, 0}, Material::Wall);
  add({-1, -2}, {13, -2}, Material::Wall);  // room wall behind the pane
  add({-1, -2}, {-1, 3}, Material::Wall);   // ends
  add({13, -2}, {13, 3}, Material::Wall);
  return m;
}

// reflect_probability: share of the beams that meet the pane away from its normal and come back
// folded (a stand-in for the Fresnel reflectance, raised so the phantom is well populated).
LaserLog corridorLog(double reflect_probability, std::uint64_t seed) {
  const VectorMap map = corridor();
  const RayCaster caster(map);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.01);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  LaserLog log;
  for (double x = 0.5; x <= 11.5; x += 0.05) {
    LaserScan scan;
    scan.max_range = 20.0;
    scan.start_angle = deg2rad(-135.0);
    scan.angular_step = deg2rad(1.0);
    scan.laser_pose = Pose2(x, 1.0, 0.0);
    for (int i = 0; i < 271; ++i) {
      const double a = scan.laser_pose.theta + scan.beamAngle(i);
      Vec2 dir(std::cos(a), std::sin(a));
      Vec2 origin = scan.laser_pose.t;
      double travelled = 0.0;
      RayHit hit = caster.cast(origin, dir, scan.max_range);
      std::int32_t skip = -1;
      while (hit.hit() && hit.material == Material::Glass) {
        const double p_direct = 0.9 * std::exp(-std::pow(rad2deg(hit.incidence), 2) / (2 * 4.0));
        const double p = u(rng);
        if (p < p_direct) break;  // direct return from the pane
        travelled += hit.range;
        origin = origin + hit.range * dir;
        skip = hit.segment;
        if (p < p_direct + reflect_probability) dir = Vec2(dir.x(), -dir.y());  // folded by the pane
        hit = caster.cast(origin, dir, scan.max_range - travelled, skip);
      }
      scan.ranges.push_back(hit.hit() ? static_cast<float>(travelled + hit.range + noise(rng))
                                      : static_cast<float>(scan.max_range));
    }
    log.scans.push_back(std::move(scan));
  }
  return log;
}

// Wall or glass cells in the band y in [y0, y1], x in [1, 11].
int nonEmptyCells(const CellEvidence& e, double y0, double y1) {
  int n = 0;
  const auto& g = e.geometry;
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const Vec2 c = g.origin + (Vec2(x, y) + Vec2(0.5, 0.5)) * g.resolution;
      if (c.x() < 1.0 || c.x() > 11.0 || c.y() < y0 || c.y() > y1) continue;
      const int l = e.label[g.index(x, y)];
      n += l == kOccupied || isGlass(l);
    }
  return n;
}

TEST(MirrorPhantoms, FoldedReturnsBehindAWallAreClearedAndRealWallsStay) {
  const LaserLog log = corridorLog(0.3, 7);
  MappingOptions options;
  MappingResult mapped = mapLog(log, options);
  CellEvidence& e = mapped.evidence;
  const int phantom_before = nonEmptyCells(e, -3.3, -2.7);
  const int room_wall_before = nonEmptyCells(e, -2.15, -1.85);
  const int pane_before = nonEmptyCells(e, -0.15, 0.15);
  const int corridor_wall_before = nonEmptyCells(e, 2.85, 3.15);
  ASSERT_GT(phantom_before, 100) << "the scene must produce a phantom wall for the test to mean anything";
  ASSERT_GT(room_wall_before, 150);
  ASSERT_GT(pane_before, 120);

  const PhantomStats st = suppressMirrorPhantoms(log, options.beams, PhantomOptions{}, e);
  EXPECT_GT(st.beams_through_glass, st.folded_beams);
  EXPECT_GT(st.folded_beams, 1000u);
  EXPECT_GE(st.cells_cleared, static_cast<std::size_t>(0.9 * phantom_before));
  EXPECT_LE(nonEmptyCells(e, -3.3, -2.7), phantom_before / 20);
  EXPECT_GE(nonEmptyCells(e, -2.15, -1.85), room_wall_before * 95 / 100);
  EXPECT_EQ(nonEmptyCells(e, -0.15, 0.15), pane_before);
  EXPECT_EQ(nonEmptyCells(e, 2.85, 3.15), corridor_wall_before);
}

TEST(MirrorPhantoms, NothingIsClearedWithoutFoldedBeams) {
  const LaserLog log = corridorLog(0.0, 7);
  MappingOptions options;
  MappingResult mapped = mapLog(log, options);
  const std::vector<std::uint8_t> before = mapped.evidence.label;
  const PhantomStats st = suppressMirrorPhantoms(log, options.beams, PhantomOptions{}, mapped.evidence);
  EXPECT_GT(st.beams_through_glass, 10000u);
  EXPECT_EQ(st.cells_cleared, 0u);
  const auto& g = mapped.evidence.geometry;
  for (std::size_t i = 0; i < before.size(); ++i)
    if (before[i] != mapped.evidence.label[i])
      ADD_FAILURE() << "cleared cell at "
                    << (g.origin + (Vec2(i % g.width, i / g.width) + Vec2(0.5, 0.5)) * g.resolution).transpose()
                    << " label " << int(before[i]);
}

TEST(MirrorPhantoms, AMapWithoutGlassIsLeftAlone) {
  LaserLog log = corridorLog(0.3, 7);
  MappingOptions options;
  MappingResult mapped = mapLog(log, options);
  for (std::uint8_t& l : mapped.evidence.label)
    if (isGlass(l)) l = kOccupied;
  const std::vector<std::uint8_t> before = mapped.evidence.label;
  const PhantomStats st = suppressMirrorPhantoms(log, options.beams, PhantomOptions{}, mapped.evidence);
  EXPECT_EQ(st.beams_through_glass, 0u);
  EXPECT_EQ(mapped.evidence.label, before);
}

}  // namespace
}  // namespace glassmap::glass
