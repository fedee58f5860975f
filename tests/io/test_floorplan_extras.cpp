// The extra layers of a floorplan (clutter, doors, rooms) in GPKG, GeoJSON and DXF: written, read
// back, doors and rooms skipped by readFloorplan, clutter read as walls unless the building alone
// is asked for, left out of the one-layer formats; and georeferenced plans at 10^6 m coordinates read back in their map frame to well
// under a millimetre.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "glassmap/core/angles.hpp"
#include "glassmap/io/floorplan.hpp"
#include "glassmap/io/floorplan_extras.hpp"
#include "io_test_util.hpp"

namespace glassmap {
namespace {

namespace fs = std::filesystem;

VectorMap building() {
  VectorMap m;
  m.add({0, 0}, {8, 0}, Material::Wall).thickness = 0.2;
  m.add({8, 0}, {8, 5}, Material::Wall);
  m.add({8, 5}, {0, 5}, Material::Wall);
  m.add({0, 5}, {0, 0}, Material::Glass).pane_angle = 0.0;
  m.add({4, 0}, {4, 2}, Material::Wall);
  m.add({4, 3}, {4, 5}, Material::Wall);
  return m;
}

FloorplanExtras extras() {
  FloorplanExtras x;
  x.clutter.add({1, 1}, {2.5, 1}, Material::Wall).thickness = 0.05;
  x.clutter.add({2.5, 1}, {2.5, 1.8}, Material::Wall);
  x.doors.push_back({{4, 2}, {4, 3}});
  RoomPolygon left{{{0, 0}, {4, 0}, {4, 5}, {0, 5}}, 20.0, 1};
  RoomPolygon right{{{4, 0}, {8, 0}, {8, 5}, {4, 5}}, 20.0, 2};
  x.rooms = {left, right};
  return x;
}

class ExtrasRoundTrip : public ::testing::TestWithParam<const char*> {};

TEST_P(ExtrasRoundTrip, LayersComeBackAndAreNotSurfaces) {
  test::TempDir dir;
  const fs::path f = dir / (std::string("plan.") + GetParam());
  writeFloorplan(f, building(), extras());
  // By default every surface: the building and its clutter (as walls); the building alone when asked.
  EXPECT_EQ(readFloorplan(f).segments.size(), building().segments.size() + 2);
  FloorplanReadOptions building_only;
  building_only.clutter = false;
  const VectorMap walls = readFloorplan(f, building_only);
  EXPECT_EQ(walls.segments.size(), building().segments.size());
  EXPECT_EQ(walls.count(Material::Glass), 1u);
  const FloorplanExtras back = readFloorplanExtras(f);
  ASSERT_EQ(back.clutter.segments.size(), 2u);
  EXPECT_LT((back.clutter.segments[0].b - Vec2(2.5, 1)).norm(), 1e-9);
  ASSERT_EQ(back.doors.size(), 1u);
  EXPECT_NEAR(back.doors[0].width(), 1.0, 1e-9);
  ASSERT_EQ(back.rooms.size(), 2u);
  EXPECT_EQ(back.rooms[0].ring.size(), 4u);
  EXPECT_NEAR(back.rooms[1].area, 20.0, 1e-9);
}

INSTANTIATE_TEST_SUITE_P(Formats, ExtrasRoundTrip, ::testing::Values("gpkg", "geojson", "dxf"));

TEST(FloorplanExtras, OneLayerFormatsKeepTheBuildingOnly) {
  test::TempDir dir;
  for (const char* ext : {"shp", "fgb"}) {
    const fs::path f = dir / (std::string("plan.") + ext);
    writeFloorplan(f, building(), extras());
    EXPECT_EQ(readFloorplan(f).segments.size(), building().segments.size()) << ext;
    EXPECT_TRUE(readFloorplanExtras(f).empty()) << ext;
  }
}

// 10^6 m eastings and northings: a plan written in the building's CRS and read back in its map
// frame keeps every coordinate to a micrometre, extras too.
TEST(FloorplanExtras, GeoreferencedAtAMillionMetresLosesNothing) {
  test::TempDir dir;
  FloorplanGeoref g;
  g.crs = "EPSG:25832";
  g.origin = Pose2(987654.321, 5432109.876, deg2rad(37.5));
  for (const char* ext : {"gpkg", "geojson"}) {
    const fs::path f = dir / (std::string("plan.") + ext);
    writeFloorplan(f, building(), extras(), &g);
    FloorplanReadOptions building_only;
    building_only.clutter = false;
    const VectorMap back = readFloorplan(f, building_only);
    ASSERT_EQ(back.segments.size(), building().segments.size()) << ext;
    for (std::size_t i = 0; i < back.segments.size(); ++i) {
      EXPECT_LT((back.segments[i].a - building().segments[i].a).norm(), 1e-6) << ext;
      EXPECT_LT((back.segments[i].b - building().segments[i].b).norm(), 1e-6) << ext;
    }
    const FloorplanExtras x = readFloorplanExtras(f);
    ASSERT_EQ(x.rooms.size(), 2u);
    EXPECT_LT((x.rooms[1].ring[2] - Vec2(8, 5)).norm(), 1e-6) << ext;
    ASSERT_EQ(x.doors.size(), 1u);
    EXPECT_LT((x.doors[0].a - Vec2(4, 2)).norm(), 1e-6) << ext;
    // In the building's CRS when asked: the far corner where the origin puts it.
    FloorplanReadOptions building_frame = building_only;
    building_frame.building_frame = true;
    const VectorMap placed = readFloorplan(f, building_frame);
    EXPECT_LT((placed.segments[1].b - g.origin * Vec2(8, 5)).norm(), 1e-6) << ext;
  }
}

}  // namespace
}  // namespace glassmap
