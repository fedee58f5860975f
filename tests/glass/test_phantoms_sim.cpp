// Mirror phantoms drawn by a simulated laser (glassmap::sim): panes folded into the rooms.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "glass_sim_test_util.hpp"
#include "glassmap/glass/mapping.hpp"
#include "glassmap/glass/phantoms.hpp"

namespace glassmap::glass {
namespace {

// Panes along y = 0 and y = y2 (x 0 .. 12) in a box from lo to hi, seen from a path along y = 1 by a
// laser whose glass returns almost always near the normal (15 deg lobe) and reflects half the rest.
testing::Classified twoPanes(double y2, const Vec2& lo, const Vec2& hi) {
  sim::Scene scene;
  scene.map.add({0, 0}, {12, 0}, Material::Glass);
  scene.map.add({0, y2}, {12, y2}, Material::Glass);
  testing::addBox(scene.map, lo, hi);
  scene.trajectory.waypoints = {{1, 1}, {11, 1}};
  scene.trajectory.speed = 0.5;
  scene.laser.rate = 10.0;
  scene.glass.direct_sigma_deg = 15.0;
  scene.glass.direct_peak = 1.0;
  scene.glass.reflection_floor = 0.5;
  return testing::simulateAndClassify(scene);
}

// Two parallel panes (y = 0 and y = 2) with open rooms behind them, seen by a laser whose glass
// returns almost always near the normal (15 deg lobe) and reflects half the rest. A beam folded by
// one pane that comes back directly from the other draws a phantom pane inside the room behind the
// first, mirrored across it: hits from one angle, the very signature of glass, and no wall in
// between to tell. Its mirror image is the real pane, which is the test.
TEST(MirrorPhantoms, PhantomPanesMirroringARealPaneAreCleared) {
  testing::Classified c = twoPanes(2.0, {-1, -5}, {13, 7});
  CellEvidence& e = c.mapped.evidence;
  // Glass cells inside the rooms (beyond either pane, short of the rooms' walls) are phantoms.
  auto phantoms = [&] {
    std::size_t n = 0, real = 0;
    const grid::GridGeometry& g = e.geometry;
    for (int y = 0; y < g.height; ++y)
      for (int x = 0; x < g.width; ++x) {
        if (!isGlass(e.label[g.index(x, y)])) continue;
        const double wy = g.origin.y() + (y + 0.5) * g.resolution;
        if ((wy < -0.3 && wy > -4.7) || (wy > 2.3 && wy < 6.7))
          ++n;
        else if (std::abs(wy) < 0.15 || std::abs(wy - 2) < 0.15)
          ++real;
      }
    return std::pair{n, real};
  };
  const auto [before, real_before] = phantoms();
  const PhantomStats s = suppressMirrorPhantoms(c.log, c.options.beams, PhantomOptions{}, e);
  const auto [after, real_after] = phantoms();
  std::printf("phantom panes: %zu glass cells in the rooms before, %zu after; real pane cells %zu -> %zu\n", before,
              after, real_before, real_after);
  EXPECT_GT(before, 100u);
  EXPECT_LT(after, before / 5);
  EXPECT_GE(real_after, real_before * 95 / 100);
  EXPECT_GT(s.cells_cleared, 0u);
}

// Glass cells of e whose centre (x, y) [m] `where` accepts.
template <class Where>
std::size_t glassCellsWhere(const CellEvidence& e, Where&& where) {
  std::size_t n = 0;
  const grid::GridGeometry& g = e.geometry;
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const Vec2 c = g.origin + (Vec2(x, y) + Vec2(0.5, 0.5)) * g.resolution;
      n += isGlass(e.label[g.index(x, y)]) && where(c.x(), c.y());
    }
  return n;
}

// A corridor (y = 0 .. 2, a wall at y = 2) with a pane along y = 0 and a second pane behind it
// (y = -1.5), a room behind both. A beam that passes the first pane, is folded by the second and
// comes back directly from the first draws a phantom pane at y = -3: its mirror image across the
// first pane crossed (y = 3) lies outside the building, across the second (y = 0) it is the real
// pane. Every pane the beam crossed is a candidate fold, not just the first (random:21's glass room,
// stop 44).
TEST(MirrorPhantoms, APaneSeenThroughAnotherFoldsToo) {
  testing::Classified c = twoPanes(-1.5, {-1, -7}, {13, 2});
  CellEvidence& e = c.mapped.evidence;
  // Glass cells in the room behind the second pane, beyond what a fold at the first can reach
  // (its images of the corridor wall lie at y = -2): the phantom at y = -3 and the corridor wall
  // folded by the second pane (y = -5).
  auto behind = [&] {
    return glassCellsWhere(e, [](double x, double y) { return x > 1.0 && x < 11.0 && y < -2.6 && y > -6.7; });
  };
  auto real = [&] {
    return glassCellsWhere(e, [](double, double y) { return std::abs(y) < 0.15 || std::abs(y + 1.5) < 0.15; });
  };
  const std::size_t before = behind(), real_before = real();
  suppressMirrorPhantoms(c.log, c.options.beams, PhantomOptions{}, e);
  const std::size_t after = behind(), real_after = real();
  std::printf("behind the second pane: %zu glass cells before, %zu after; real pane cells %zu -> %zu\n", before, after,
              real_before, real_after);
  EXPECT_GT(before, 40u);
  EXPECT_LT(after, before / 2);  // the first pane's fold alone clears none of them
  EXPECT_GE(real_after, real_before * 95 / 100);
}

}  // namespace
}  // namespace glassmap::glass
