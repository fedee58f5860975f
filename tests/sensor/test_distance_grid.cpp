// The distance grid's memory follows the segments, not the map's bounding box: a stray segment
// far from the building costs a few tiles, and distances are those of a grid without tiles.
#include <gtest/gtest.h>

#include <random>

#include "glassmap/core/error.hpp"
#include "glassmap/sensor/field_model.hpp"

namespace glassmap::sensor {
namespace {

VectorMap room() {
  VectorMap m;
  m.add({0, 0}, {10, 0}, Material::Wall);
  m.add({10, 0}, {10, 6}, Material::Wall);
  m.add({10, 6}, {0, 6}, Material::Glass);
  m.add({0, 6}, {0, 0}, Material::Wall);
  m.add({4, 2}, {6, 2.5}, Material::Wall);
  return m;
}

TEST(DistanceGrid, AStrayFarAwayCostsTilesNotTheBoundingBox) {
  const DistanceGrid alone(room(), true, 0.025, 1.0);
  for (const double far : {1e3, 2e4}) {
    VectorMap m = room();
    m.add({far, far}, {far + 1.0, far}, Material::Wall);
    const DistanceGrid grid(m, true, 0.025, 1.0);
    // A dense grid over the box would hold (far / 0.025)^2 samples: 1.6e9 at 1 km.
    EXPECT_LT(grid.samples(), alone.samples() + 1'000'000u) << far;
    EXPECT_LT(grid.bytes(), 64u << 20) << far;
    // The same distances inside the room, and the stray's own neighbourhood is there.
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> ux(-0.5, 10.5), uy(-0.5, 6.5);
    for (int k = 0; k < 2000; ++k) {
      const Vec2 p(ux(rng), uy(rng));
      ASSERT_NEAR(grid.distance(p), alone.distance(p), 1e-6) << p.transpose();
    }
    EXPECT_NEAR(grid.distance({far + 0.5, far + 0.3}), 0.3, 0.03);
    EXPECT_DOUBLE_EQ(grid.distance({far / 2, far / 2}), 1.0);
  }
}

TEST(DistanceGrid, TiledReadsMatchExactDistancesAcrossTileBorders) {
  // A long wall crosses many 64-cell tiles: every read, on tile borders too, is within one cell
  // of the exact distance.
  VectorMap m;
  m.add({0, 0}, {37.3, 11.1}, Material::Wall);
  const DistanceGrid grid(m, true, 0.05, 2.0);
  EXPECT_GT(grid.tiles(), 8u);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> ux(-1, 38), uy(-1, 12);
  for (int k = 0; k < 20000; ++k) {
    const Vec2 p(ux(rng), uy(rng));
    ASSERT_NEAR(grid.distance(p), grid.exactDistance(p), 0.05) << p.transpose();
  }
}

TEST(DistanceGrid, RefusesSegmentsOfAbsurdLengthBeforeAllocating) {
  VectorMap m = room();
  m.add({0, 0}, {1e7, 1e7}, Material::Wall);  // a 14,000 km diagonal
  EXPECT_THROW(DistanceGrid(m, true, 0.025, 1.0), Error);
}

}  // namespace
}  // namespace glassmap::sensor
