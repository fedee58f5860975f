// Floorplans written in a building's projected CRS: coordinates moved by the map frame's origin,
// the CRS carried (GPKG, GeoJSON's "crs" member), the origin recorded, bad CRSs refused.
#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <ogrsf_frmts.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "glassmap/core/angles.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/io/floorplan.hpp"

namespace glassmap {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / "glassmap_test_georef";
  fs::create_directories(dir);
  return dir / name;
}

VectorMap plan() {
  VectorMap m;
  m.add({0, 0}, {10, 0}, Material::Wall);
  m.add({10, 0}, {10, 5}, Material::Glass);
  m.segments.back().pane_angle = 0.0;
  return m;
}

// Difference of two axial angles (period pi) [rad].
double axialDiff(double a, double b) { return std::abs(std::remainder(a - b, kPi)); }

TEST(Georeference, GpkgCarriesTheCrsTheOriginAndMovedCoordinates) {
  FloorplanGeoref g;
  g.crs = "EPSG:25832";
  g.origin = Pose2(500000.0, 5400000.0, kPi / 2);
  const fs::path f = scratch("plan.gpkg");
  writeFloorplan(f, plan(), g);
  FloorplanReadOptions building;
  building.building_frame = true;
  const VectorMap back = readFloorplan(f, building);
  ASSERT_EQ(back.segments.size(), 2u);
  // (10, 0) in the map frame: 10 m north of the origin after a quarter turn.
  EXPECT_NEAR(back.segments[0].b.x(), 500000.0, 1e-6);
  EXPECT_NEAR(back.segments[0].b.y(), 5400010.0, 1e-6);
  EXPECT_EQ(back.segments[1].material, Material::Glass);
  EXPECT_LT(axialDiff(back.segments[1].pane_angle, kPi / 2), 1e-9);
  // Read as localize, eval and export read it: back in the map frame, told by the file alone.
  FloorplanReadReport report;
  FloorplanReadOptions plain;
  plain.report = &report;
  const VectorMap map_frame = readFloorplan(f, plain);
  ASSERT_EQ(map_frame.segments.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_LT((map_frame.segments[i].a - plan().segments[i].a).norm(), 1e-6);
    EXPECT_LT((map_frame.segments[i].b - plan().segments[i].b).norm(), 1e-6);
  }
  EXPECT_LT(axialDiff(map_frame.segments[1].pane_angle, 0.0), 1e-9);
  ASSERT_FALSE(report.notes.empty());
  EXPECT_NE(report.notes.back().find("map frame"), std::string::npos);
  GDALAllRegister();
  GDALDatasetUniquePtr ds(GDALDataset::Open(f.string().c_str(), GDAL_OF_VECTOR));
  ASSERT_TRUE(ds);
  OGRLayer* layer = ds->GetLayer(0);
  ASSERT_NE(layer->GetSpatialRef(), nullptr);
  EXPECT_STREQ(layer->GetSpatialRef()->GetAuthorityCode(nullptr), "25832");
  const char* origin = layer->GetMetadataItem("GLASSMAP_MAP_FRAME_ORIGIN");
  ASSERT_NE(origin, nullptr);
  std::istringstream in(origin);
  double e = 0, n = 0, rot = 0;
  in >> e >> n >> rot;
  EXPECT_DOUBLE_EQ(e, 500000.0);
  EXPECT_DOUBLE_EQ(n, 5400000.0);
  EXPECT_NEAR(rot, kPi / 2, 1e-12);
}

TEST(Georeference, GeoJsonNamesItsCrs) {
  FloorplanGeoref g;
  g.crs = "EPSG:25832";
  g.origin = Pose2(500000.0, 5400000.0, 0.0);
  const fs::path f = scratch("plan.geojson");
  writeFloorplan(f, plan(), g);
  std::ifstream in(f);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("EPSG::25832"), std::string::npos);
  // Its description records the map frame: read back there, or in the CRS when asked.
  const VectorMap back = readFloorplan(f);
  ASSERT_EQ(back.segments.size(), 2u);
  EXPECT_NEAR(back.segments[0].b.x(), 10.0, 1e-6);
  FloorplanReadOptions building;
  building.building_frame = true;
  EXPECT_NEAR(readFloorplan(f, building).segments[0].b.x(), 500010.0, 1e-6);
}

TEST(Georeference, RefusesGeographicAndUnknownCrs) {
  FloorplanGeoref g;
  g.origin = Pose2(1.0, 2.0, 0.0);
  g.crs = "EPSG:4326";
  EXPECT_THROW(writeFloorplan(scratch("bad.gpkg"), plan(), g), Error);
  g.crs = "EPSG:999999";
  EXPECT_THROW(writeFloorplan(scratch("bad.gpkg"), plan(), g), Error);
  g.crs = "EPSG:2249";  // US survey feet
  EXPECT_THROW(writeFloorplan(scratch("bad.gpkg"), plan(), g), Error);
  EXPECT_FALSE(fs::exists(scratch("bad.gpkg")));
}

}  // namespace
}  // namespace glassmap
