#include <gtest/gtest.h>

#include "glassmap/core/error.hpp"
#include "glassmap/io/floorplan.hpp"
#include "io_test_util.hpp"

namespace glassmap {
namespace {

TEST(FloorplanUnits, NamesAndNumbersParse) {
  EXPECT_DOUBLE_EQ(parseLengthUnit("m"), 1.0);
  EXPECT_DOUBLE_EQ(parseLengthUnit("MM"), 0.001);
  EXPECT_DOUBLE_EQ(parseLengthUnit("in"), 0.0254);
  EXPECT_DOUBLE_EQ(parseLengthUnit("ft"), 0.3048);
  EXPECT_NEAR(parseLengthUnit("us-ft"), 0.3048006, 1e-7);
  EXPECT_DOUBLE_EQ(parseLengthUnit("0.5"), 0.5);
  for (const char* bad : {"", "furlong", "-1", "0", "1m", "nan"}) EXPECT_THROW(parseLengthUnit(bad), Error) << bad;
}

TEST(FloorplanUnits, ImplausibleExtentsAreNamedWithTheUnitsAssumed) {
  VectorMap m;
  m.add({0, 0}, {0.7, 0.4}, Material::Wall);
  const FloorplanUnits inches{0.0254, "DXF $INSUNITS (inches)"};
  const std::string w = implausibleExtentWarning(m, inches, "plan.dxf");
  EXPECT_NE(w.find("plan.dxf"), std::string::npos) << w;
  EXPECT_NE(w.find("inches"), std::string::npos) << w;
  EXPECT_NE(w.find("--units"), std::string::npos) << w;
  m.segments.clear();
  m.add({0, 0}, {40, 0}, Material::Wall);
  m.add({40, 0}, {40, 25}, Material::Wall);
  m.add({40, 25}, {0, 25}, Material::Glass);
  m.add({0, 25}, {0, 0}, Material::Wall);
  EXPECT_TRUE(implausibleExtentWarning(m, inches, "plan.dxf").empty());
  m.add({20000, 0}, {20001, 0}, Material::Wall);  // a stray far away: still a building
  EXPECT_TRUE(implausibleExtentWarning(m, {1.0, "none declared: metres"}, "plan.dxf").empty());
  VectorMap mm;  // a 40 x 25 m floor drawn in millimetres, read as metres
  mm.add({0, 0}, {40000, 0}, Material::Wall);
  mm.add({40000, 0}, {40000, 25000}, Material::Wall);
  EXPECT_FALSE(implausibleExtentWarning(mm, {1.0, "none declared: metres"}, "plan.dxf").empty());
}

TEST(FloorplanUnits, TheReaderSaysWhatItAssumed) {
  test::TempDir dir;
  const auto p = dir.write("plan.geojson",
                           R"({"type":"FeatureCollection","features":[{"type":"Feature","properties":{"material":"wall"},)"
                           R"("geometry":{"type":"LineString","coordinates":[[0,0],[4000,0]]}}]})");
  FloorplanUnits u;
  FloorplanReadOptions o;
  o.units = &u;
  EXPECT_NEAR(readFloorplan(p, o).segments.at(0).length(), 4000.0, 1e-9);
  EXPECT_DOUBLE_EQ(u.unit_in_metres, 1.0);
  EXPECT_NE(u.source.find("metres"), std::string::npos);
  o.unit_in_metres = parseLengthUnit("mm");
  EXPECT_NEAR(readFloorplan(p, o).segments.at(0).length(), 4.0, 1e-9);
  EXPECT_NE(u.source.find("option"), std::string::npos);
}

}  // namespace
}  // namespace glassmap
