// Mirror phantoms drawn by a simulated laser (glassmap::sim): panes folded into the rooms.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "glass_sim_test_util.hpp"
#include "glassmap/glass/mapping.hpp"
#include "glassmap/glass/phantoms.hpp"

namespace glassmap::glass {
namespace {

// Two parallel panes (y = 0 and y = 2) with open rooms behind them, seen by a laser whose glass
// returns almost always near the normal (15 deg lobe) and reflects half the rest. A beam folded by
// one pane that comes back directly from the other draws a phantom pane inside the room behind the
// first, mirrored across it: hits from one angle, the very signature of glass, and no wall in
// between to tell. Its mirror image is the real pane, which is the test.
TEST(MirrorPhantoms, PhantomPanesMirroringARealPaneAreCleared) {
  sim::Scene scene;
  VectorMap& m = scene.map;
  m.add({0, 0}, {12, 0}, Material::Glass);
  m.add({0, 2}, {12, 2}, Material::Glass);
  testing::addBox(m, {-1, -5}, {13, 7});
  scene.trajectory.waypoints = {{1, 1}, {11, 1}};
  scene.trajectory.speed = 0.5;
  scene.laser.rate = 10.0;
  scene.glass.direct_sigma_deg = 15.0;
  scene.glass.direct_peak = 1.0;
  scene.glass.reflection_floor = 0.5;
  testing::Classified c = testing::simulateAndClassify(scene);
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

}  // namespace
}  // namespace glassmap::glass
