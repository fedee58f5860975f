#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

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
  const auto p = dir.write(
      "plan.geojson", R"({"type":"FeatureCollection","features":[{"type":"Feature","properties":{"material":"wall"},)"
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

namespace glassmap {
namespace {

std::string rectangle(double x0, double y0, double w, double h, const std::string& crs_member = "") {
  char buf[1024];
  std::snprintf(
      buf, sizeof buf,
      R"({"type":"FeatureCollection",%s"features":[{"type":"Feature","properties":{"material":"wall"},)"
      R"("geometry":{"type":"LineString","coordinates":[[%.9f,%.9f],[%.9f,%.9f],[%.9f,%.9f],[%.9f,%.9f],[%.9f,%.9f]]}}]})",
      crs_member.c_str(), x0, y0, x0 + w, y0, x0 + w, y0 + h, x0, y0 + h, x0, y0);
  return buf;
}

Vec2 extentOf(const VectorMap& m) {
  const Eigen::AlignedBox2d b = m.bounds();
  return b.max() - b.min();
}

TEST(GeoJsonCrs, Rfc7946LongitudeLatitudeBecomesLocalMetres) {
  // A 40 x 20 m building in Zurich as an OpenStreetMap or IMDF export has it: degrees, no crs.
  test::TempDir dir;
  const double lat = 47.37, dlon = 40.0 / (111319.49 * std::cos(lat * M_PI / 180.0)), dlat = 20.0 / 111132.95;
  const auto p = dir.write("osm.geojson", rectangle(8.54, lat, dlon, dlat));
  FloorplanUnits u;
  FloorplanReadOptions o;
  o.units = &u;
  const Vec2 size = extentOf(readFloorplan(p, o));
  EXPECT_NEAR(size.x(), 40.0, 0.2) << u.source;
  EXPECT_NEAR(size.y(), 20.0, 0.1) << u.source;
  EXPECT_NE(u.source.find("longitude/latitude"), std::string::npos) << u.source;
}

TEST(GeoJsonCrs, ADeclaredCrsIsHonoured) {
  // NAD83 / New York Long Island (US survey feet), old-style crs member.
  test::TempDir dir;
  const double ft = 1200.0 / 3937.0;
  const auto p = dir.write("feet.geojson",
                           rectangle(300000, 60000, 40.0 / ft, 20.0 / ft,
                                     R"("crs":{"type":"name","properties":{"name":"urn:ogc:def:crs:EPSG::2263"}},)"));
  FloorplanUnits u;
  FloorplanReadOptions o;
  o.units = &u;
  const Vec2 size = extentOf(readFloorplan(p, o));
  EXPECT_NEAR(size.x(), 40.0, 1e-6) << u.source;
  EXPECT_NEAR(size.y(), 20.0, 1e-6) << u.source;
}

TEST(GeoJsonCrs, LocalMetresStayMetresAndSaySo) {
  test::TempDir dir;
  FloorplanUnits u;
  FloorplanReadOptions o;
  o.units = &u;
  // Unmarked, plausible as metres (and also valid degrees): metres, with the assumption named.
  const auto p = dir.write("local.geojson", rectangle(1, 1, 29, 13));
  EXPECT_NEAR(extentOf(readFloorplan(p, o)).x(), 29.0, 1e-9);
  EXPECT_NE(u.source.find("assumed"), std::string::npos) << u.source;
  // glassmap's own GeoJSON carries its marker: read as local metres without doubt.
  VectorMap tiny;
  tiny.add({0, 0}, {0.5, 0.3}, Material::Glass);
  writeFloorplan(dir.path() / "ours.geojson", tiny);
  const VectorMap back = readFloorplan(dir.path() / "ours.geojson", o);
  EXPECT_NEAR(back.segments.at(0).length(), tiny.segments[0].length(), 1e-9);
  EXPECT_NE(u.source.find("glassmap"), std::string::npos) << u.source;
}

}  // namespace
}  // namespace glassmap
