#include <gtest/gtest.h>

#include <cmath>

#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <fstream>
#include <iterator>
#include <set>

#include "glassmap/core/error.hpp"
#include "glassmap/io/floorplan.hpp"
#include "io_test_util.hpp"

namespace glassmap {
namespace {

using test::TempDir;

// The tests below also use GDAL directly.
const bool kGdalRegistered = (GDALAllRegister(), true);

VectorMap sampleMap() {
  VectorMap m;
  auto add = [&](Vec2 a, Vec2 b, Material mat, double thick, double angle = 0.0, std::uint32_t support = 0,
                 double evidence = 0.0) {
    MapSegment s;
    s.a = a;
    s.b = b;
    s.material = mat;
    s.thickness = thick;
    s.pane_angle = angle;
    s.support = support;
    s.evidence = evidence;
    m.segments.push_back(s);
  };
  add({0.0, 0.0}, {10.123456789, 0.0}, Material::Wall, 0.2);
  add({10.123456789, 0.0}, {10.123456789, 7.654321}, Material::Wall, 0.15);
  add({1.0 / 3.0, 7.654321}, {-2.0 / 7.0, 3.25}, Material::Glass, 0.008, 1.2345, 42, 0.875);
  add({-1234.5678901, 987.654321}, {-1230.0, 990.5}, Material::Glass, 0.012, 3.0, 7, 0.5);
  add({5.0, 5.0}, {5.0, 6.0}, Material::Wall, 0.1);
  return m;
}

void expectSameMap(const VectorMap& a, const VectorMap& b, double tol_m) {
  ASSERT_EQ(a.segments.size(), b.segments.size());
  for (std::size_t i = 0; i < a.segments.size(); ++i) {
    SCOPED_TRACE("segment " + std::to_string(i));
    const MapSegment& s = a.segments[i];
    const MapSegment& r = b.segments[i];
    EXPECT_LE((s.a - r.a).norm(), tol_m);
    EXPECT_LE((s.b - r.b).norm(), tol_m);
    EXPECT_EQ(s.material, r.material);
    EXPECT_NEAR(s.thickness, r.thickness, 1e-9);
    EXPECT_NEAR(s.pane_angle, r.pane_angle, 1e-9);
    EXPECT_EQ(s.support, r.support);
    EXPECT_NEAR(s.evidence, r.evidence, 1e-9);
  }
}

std::set<std::string> filesIn(const std::filesystem::path& dir) {
  std::set<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir)) names.insert(e.path().filename().string());
  return names;
}

class FloorplanRoundTrip : public ::testing::TestWithParam<std::string> {};

TEST_P(FloorplanRoundTrip, ReadsBackEqual) {
  TempDir dir;
  const VectorMap map = sampleMap();
  const auto path = dir / ("plan" + GetParam());
  writeFloorplan(path, map);
  ASSERT_TRUE(std::filesystem::exists(path));
  const VectorMap back = readFloorplan(path);
  expectSameMap(map, back, 1e-6);
  EXPECT_EQ(back.count(Material::Glass), 2u);
  // Nothing but the output (and a shapefile's sidecars) is left in the folder.
  for (const std::string& name : filesIn(dir.path())) EXPECT_EQ(name.rfind("plan.", 0), 0u) << name;
  // Writing again over an existing file works (atomic replace).
  writeFloorplan(path, map);
  expectSameMap(map, readFloorplan(path), 1e-6);
}

INSTANTIATE_TEST_SUITE_P(Io, FloorplanRoundTrip, ::testing::Values(".gpkg", ".geojson", ".shp", ".fgb", ".dxf"),
                         [](const auto& info) { return info.param.substr(1); });

TEST(Floorplan, FormatFromExtension) {
  ASSERT_TRUE(kGdalRegistered);
  EXPECT_EQ(floorplanFormatFromPath("a/b.GPKG"), FloorplanFormat::Gpkg);
  EXPECT_EQ(floorplanFormatFromPath("b.json"), FloorplanFormat::GeoJson);
  EXPECT_EQ(floorplanFormatFromPath("b.geojson"), FloorplanFormat::GeoJson);
  EXPECT_EQ(floorplanFormatFromPath("b.shp"), FloorplanFormat::Shapefile);
  EXPECT_EQ(floorplanFormatFromPath("b.fgb"), FloorplanFormat::FlatGeobuf);
  EXPECT_EQ(floorplanFormatFromPath("b.dxf"), FloorplanFormat::Dxf);
  EXPECT_THROW(floorplanFormatFromPath("b.txt"), Error);
  EXPECT_THROW(floorplanFormatFromPath("noext"), Error);
  TempDir dir;
  EXPECT_THROW(writeFloorplan(dir / "x.kml", sampleMap()), Error);
  EXPECT_TRUE(filesIn(dir.path()).empty());
}

TEST(Floorplan, DxfHasLayersColoursAndMetres) {
  TempDir dir;
  const auto path = dir / "plan.dxf";
  writeFloorplan(path, sampleMap());
  // Header variables: $INSUNITS 6 (metres), $MEASUREMENT 1 (metric).
  std::vector<std::string> lines;
  {
    std::ifstream in(path);
    for (std::string l; std::getline(in, l);) {
      while (!l.empty() && (l.back() == '\r' || l.back() == ' ')) l.pop_back();
      lines.push_back(l.substr(l.find_first_not_of(' ') == std::string::npos ? l.size() : l.find_first_not_of(' ')));
    }
  }
  auto headerVar = [&](const std::string& name) -> std::string {
    for (std::size_t i = 0; i + 2 < lines.size(); ++i)
      if (lines[i] == name) return lines[i + 2];
    return "missing";
  };
  EXPECT_EQ(headerVar("$INSUNITS"), "6");
  EXPECT_EQ(headerVar("$MEASUREMENT"), "1");
  // LAYER table records WALL and GLASS with distinct colours (group 62).
  auto layerColour = [&](const std::string& name) -> std::string {
    for (std::size_t i = 0; i + 1 < lines.size(); ++i) {
      if (lines[i] == "2" && lines[i + 1] == name) {
        for (std::size_t j = i + 2; j + 1 < lines.size() && lines[j] != "0"; j += 2)
          if (lines[j] == "62") return lines[j + 1];
      }
    }
    return "missing";
  };
  EXPECT_EQ(layerColour("WALL"), "7");
  EXPECT_EQ(layerColour("GLASS"), "4");
  // GDAL reads it back with features on layers WALL and GLASS.
  GDALDatasetUniquePtr ds(GDALDataset::Open(path.string().c_str(), GDAL_OF_VECTOR));
  ASSERT_TRUE(ds);
  std::multiset<std::string> layers;
  for (OGRLayer* l : ds->GetLayers())
    for (auto& f : *l) layers.insert(f->GetFieldAsString("Layer"));
  EXPECT_EQ(layers.count("WALL"), 3u);
  EXPECT_EQ(layers.count("GLASS"), 2u);
}

TEST(Floorplan, GpkgKeepsLocalMetricCrs) {
  TempDir dir;
  const auto path = dir / "plan.gpkg";
  writeFloorplan(path, sampleMap());
  GDALDatasetUniquePtr ds(GDALDataset::Open(path.string().c_str(), GDAL_OF_VECTOR));
  ASSERT_TRUE(ds);
  ASSERT_EQ(ds->GetLayerCount(), 1);
  const OGRSpatialReference* srs = ds->GetLayer(0)->GetSpatialRef();
  ASSERT_NE(srs, nullptr);
  EXPECT_TRUE(srs->IsLocal());
  EXPECT_DOUBLE_EQ(srs->GetLinearUnits(nullptr), 1.0);
  EXPECT_NE(std::string(srs->GetName()).find("glassmap"), std::string::npos) << srs->GetName();
}

TEST(Floorplan, ShapefileWritesSidecarsAndNoTemporaryFolder) {
  TempDir dir;
  writeFloorplan(dir / "plan.shp", sampleMap());
  const auto files = filesIn(dir.path());
  for (const char* f : {"plan.shp", "plan.shx", "plan.dbf", "plan.prj"}) EXPECT_TRUE(files.count(f)) << f;
  for (const auto& f : files) EXPECT_EQ(f.find("tmp"), std::string::npos) << f;
}

TEST(Floorplan, ReadsForeignSourcesWithDefaults) {
  TempDir dir;
  const auto gj = dir.write("plan.geojson", R"({"type":"FeatureCollection","features":[
    {"type":"Feature","properties":{},"geometry":{"type":"LineString","coordinates":[[0,0],[2,0],[2,3]]}},
    {"type":"Feature","properties":{"material":"Glass","thickness":0.01},
     "geometry":{"type":"MultiLineString","coordinates":[[[0,1],[0,2]],[[5,5],[6,5]]]}},
    {"type":"Feature","properties":{"material":"wall"},"geometry":{"type":"Point","coordinates":[1,1]}},
    {"type":"Feature","properties":{},"geometry":{"type":"Polygon","coordinates":[[[10,10],[11,10],[11,11],[10,10]]]}}
  ]})");
  const VectorMap m = readFloorplan(gj);
  ASSERT_EQ(m.segments.size(), 7u);  // polyline 2 + multiline 2 + triangle ring 3; the point is skipped
  EXPECT_EQ(m.segments[0].material, Material::Wall);
  EXPECT_DOUBLE_EQ(m.segments[0].thickness, 0.1);
  EXPECT_EQ(m.segments[1].a, Vec2(2, 0));
  EXPECT_EQ(m.segments[1].b, Vec2(2, 3));
  EXPECT_EQ(m.segments[2].material, Material::Glass);
  EXPECT_DOUBLE_EQ(m.segments[3].thickness, 0.01);

  // A DXF from elsewhere: layer names decide the material, thickness defaults.
  const auto dxf = dir / "cad.dxf";
  {
    GDALDriver* drv = GetGDALDriverManager()->GetDriverByName("DXF");
    ASSERT_NE(drv, nullptr);
    GDALDatasetUniquePtr ds(drv->Create(dxf.string().c_str(), 0, 0, 0, GDT_Unknown, nullptr));
    OGRLayer* l = ds->CreateLayer("entities", nullptr, wkbLineString, nullptr);
    for (const char* layer : {"A-WALL", "A-GLAZING-glass", "Facade_Glass"}) {
      OGRFeatureUniquePtr f(OGRFeature::CreateFeature(l->GetLayerDefn()));
      f->SetField("Layer", layer);
      OGRLineString ls;
      ls.addPoint(0, 0);
      ls.addPoint(1, 1);
      f->SetGeometry(&ls);
      ASSERT_EQ(l->CreateFeature(f.get()), OGRERR_NONE);
    }
  }
  const VectorMap c = readFloorplan(dxf);
  ASSERT_EQ(c.segments.size(), 3u);
  EXPECT_EQ(c.segments[0].material, Material::Wall);
  EXPECT_EQ(c.segments[1].material, Material::Glass);
  EXPECT_EQ(c.segments[2].material, Material::Glass);
  EXPECT_DOUBLE_EQ(c.segments[2].thickness, 0.1);
  // GDAL's default DXF header declares inches ($INSUNITS 1): coordinates are scaled to metres,
  // unless the caller says what a unit is.
  EXPECT_NEAR(c.segments[0].b.x(), 0.0254, 1e-12);
  FloorplanReadOptions as_metres;
  as_metres.unit_in_metres = 1.0;
  EXPECT_DOUBLE_EQ(readFloorplan(dxf, as_metres).segments[0].b.x(), 1.0);
}

TEST(Floorplan, DxfInMillimetresIsScaled) {
  TempDir dir;
  const auto path = dir / "plan.dxf";
  writeFloorplan(path, sampleMap());
  std::string text;
  {
    std::ifstream in(path, std::ios::binary);
    text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  const std::string metres = "$INSUNITS\n 70\n     6\n";
  const auto at = text.find(metres);
  ASSERT_NE(at, std::string::npos);
  text.replace(at, metres.size(), "$INSUNITS\n 70\n     4\n");
  const auto mm = dir / "mm.dxf";
  std::ofstream(mm, std::ios::binary) << text;
  const VectorMap m = readFloorplan(mm);
  ASSERT_EQ(m.segments.size(), sampleMap().segments.size());
  EXPECT_NEAR(m.segments[0].b.x(), 10.123456789e-3, 1e-12);
  EXPECT_DOUBLE_EQ(m.segments[2].thickness, 0.008);  // XDATA thickness is in metres
}

TEST(Floorplan, BadInputsAreClearErrors) {
  TempDir dir;
  const auto bad = dir.write("bad.geojson", R"({"type":"FeatureCollection","features":[
    {"type":"Feature","properties":{"material":"concrete"},"geometry":{"type":"LineString","coordinates":[[0,0],[1,0]]}}]})");
  try {
    readFloorplan(bad);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.file(), bad.string());
    EXPECT_NE(std::string(e.what()).find("material"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("concrete"), std::string::npos) << e.what();
  }
  const auto thin = dir.write("thin.geojson", R"({"type":"FeatureCollection","features":[
    {"type":"Feature","properties":{"thickness":-1},"geometry":{"type":"LineString","coordinates":[[0,0],[1,0]]}}]})");
  EXPECT_THROW(readFloorplan(thin), Error);
  EXPECT_THROW(readFloorplan(dir / "missing.gpkg"), Error);
  EXPECT_THROW(readFloorplan(dir.write("junk.gpkg", "not a geopackage")), Error);

  // Geographic coordinates (degrees) are projected to local metres about the layer's centre.
  const auto geo = dir / "geo.gpkg";
  {
    GDALDriver* drv = GetGDALDriverManager()->GetDriverByName("GPKG");
    GDALDatasetUniquePtr ds(drv->Create(geo.string().c_str(), 0, 0, 0, GDT_Unknown, nullptr));
    OGRSpatialReference wgs84;
    wgs84.importFromEPSG(4326);
    OGRLayer* l = ds->CreateLayer("lines", &wgs84, wkbLineString, nullptr);
    OGRFeatureUniquePtr f(OGRFeature::CreateFeature(l->GetLayerDefn()));
    OGRLineString ls;
    ls.addPoint(7.8, 48.0);
    ls.addPoint(7.9, 48.1);
    f->SetGeometry(&ls);
    ASSERT_EQ(l->CreateFeature(f.get()), OGRERR_NONE);
  }
  const VectorMap projected = readFloorplan(geo);
  ASSERT_EQ(projected.segments.size(), 1u);
  // 0.1 deg of longitude at 48.05 deg N is 7.44 km, 0.1 deg of latitude 11.12 km.
  EXPECT_NEAR(projected.segments[0].length(), std::hypot(7444.0, 11120.0), 0.005 * 13400.0);
  EXPECT_LT(projected.segments[0].a.norm() + projected.segments[0].b.norm(), 2 * 6800.0);  // centred

  // A map with a non-finite coordinate is refused before any file is made.
  VectorMap m = sampleMap();
  m.segments[1].b.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(writeFloorplan(dir / "nan.gpkg", m), Error);
  EXPECT_FALSE(std::filesystem::exists(dir / "nan.gpkg"));
}

}  // namespace
}  // namespace glassmap
