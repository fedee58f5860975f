// The free space random particles are drawn from: bounded by what a laser near the segments can
// see, not by the map's bounding box, and the same cells as before for an ordinary building.
#include <gtest/gtest.h>

#include <algorithm>

#include "glassmap/core/error.hpp"
#include "glassmap/localize/particle_filter.hpp"
#include "glassmap/sensor/sensor_model.hpp"

namespace glassmap::localize {
namespace {

VectorMap building() {
  VectorMap m;
  m.add({0, 0}, {30, 0}, Material::Wall);
  m.add({30, 0}, {30, 12}, Material::Glass);
  m.add({30, 12}, {0, 12}, Material::Wall);
  m.add({0, 12}, {0, 0}, Material::Wall);
  m.add({10, 0}, {10, 8}, Material::Wall);
  return m;
}

std::vector<Vec2> freeCells(const VectorMap& map, FilterOptions o = {}) {
  const auto model = sensor::makeSensorModel("beam", map);
  const ParticleFilter f(*model, o);
  return f.freeCells();
}

TEST(FreeSpace, CoversTheBuildingAwayFromItsWalls) {
  const std::vector<Vec2> cells = freeCells(building());
  // 0.1 m cells of 30 x 12 m, less a 0.2 m band along the walls: about 31,000.
  EXPECT_GT(cells.size(), 30'000u);
  EXPECT_LT(cells.size(), 36'000u);
  for (const Vec2& c : cells) {
    ASSERT_TRUE(c.x() > 0 && c.x() < 30 && c.y() > 0 && c.y() < 12) << c.transpose();
    ASSERT_GT(std::abs(c.x() - 10.0) + std::max(0.0, c.y() - 8.0), 0.19) << c.transpose();
  }
}

TEST(FreeSpace, AStrayFarAwayAddsOnlyItsNeighbourhood) {
  const std::vector<Vec2> alone = freeCells(building());
  for (const double far : {1e3, 2e4}) {
    VectorMap m = building();
    m.add({far, far}, {far + 1, far}, Material::Wall);
    const std::vector<Vec2> cells = freeCells(m);
    // The building's cells are all there (the box's corner is unchanged, so the same centres),
    // and the stray adds its reach (40 m) around it, not the void between.
    EXPECT_TRUE(std::includes(cells.begin(), cells.end(), alone.begin(), alone.end(), [](const Vec2& a, const Vec2& b) {
      return a.y() < b.y() || (a.y() == b.y() && a.x() < b.x());
    })) << far;
    EXPECT_LT(cells.size(), alone.size() + 1'200'000u) << far;
    EXPECT_GT(std::count_if(cells.begin(), cells.end(), [&](const Vec2& c) { return (c - Vec2(far, far)).norm() < 5; }),
              500);
    EXPECT_EQ(
        std::count_if(cells.begin(), cells.end(), [&](const Vec2& c) { return c.x() > 200 && c.x() < far - 100; }), 0);
  }
}

TEST(FreeSpace, RefusesSegmentsSpreadOverAContinent) {
  VectorMap m = building();
  m.add({0, 0}, {3e6, 3e6}, Material::Wall);
  EXPECT_THROW(freeCells(m), Error);
}

}  // namespace
}  // namespace glassmap::localize
