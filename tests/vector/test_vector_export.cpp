// Exporting floorplans in every format, reading them back, and vectorising rasterised scenes.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "glassmap/core/error.hpp"
#include "glassmap/eval/segments.hpp"
#include "glassmap/io/floorplan.hpp"
#include "glassmap/io/labels_raster.hpp"
#include "glassmap/vector/export.hpp"
#include "glassmap/vector/vectorize.hpp"

namespace glassmap::vector {
namespace {

namespace fs = std::filesystem;

fs::path tempDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("glassmap_test_vector_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

VectorMap sample() {
  VectorMap m;
  const auto add = [&](Vec2 a, Vec2 b, Material mat, double thick, double angle, std::uint32_t support, double ev) {
    MapSegment s;
    s.a = a;
    s.b = b;
    s.material = mat;
    s.thickness = thick;
    s.pane_angle = angle;
    s.support = support;
    s.evidence = ev;
    m.segments.push_back(s);
  };
  add({0.0, 0.0}, {10.0, 0.0}, Material::Wall, 0.15, 0.0, 210, 0.0);
  add({10.0, 0.0}, {10.0, 6.25}, Material::Wall, 0.2, 0.0, 130, 0.0);
  add({2.5, 3.0}, {7.125, 3.5}, Material::Glass, 0.012, 1.6784, 95, 0.8125);
  add({-3.5, 12.75}, {-1.0, 14.0}, Material::Glass, 0.01, 2.0344, 51, 0.5);
  return m;
}

void expectSameSegments(const VectorMap& a, const VectorMap& b, const std::string& what) {
  ASSERT_EQ(a.segments.size(), b.segments.size()) << what;
  for (std::size_t i = 0; i < a.segments.size(); ++i) {
    const MapSegment& s = a.segments[i];
    const MapSegment& t = b.segments[i];
    EXPECT_LT((s.a - t.a).norm(), 1e-6) << what << " segment " << i;
    EXPECT_LT((s.b - t.b).norm(), 1e-6) << what << " segment " << i;
    EXPECT_EQ(s.material, t.material) << what << " segment " << i;
    EXPECT_NEAR(s.thickness, t.thickness, 1e-6) << what << " segment " << i;
  }
}

TEST(Export, EveryVectorFormatReadsBackEqual) {
  const fs::path dir = tempDir("formats");
  const VectorMap map = sample();
  for (const std::string ext : {"gpkg", "geojson", "json", "shp", "fgb", "dxf"}) {
    const fs::path p = dir / ("plan." + ext);
    exportFloorplan(p, map);
    expectSameSegments(map, readFloorplan(p), ext);
  }
  fs::remove_all(dir);
}

TEST(Export, PicturesAndPdfHaveTheirSignatures) {
  const fs::path dir = tempDir("pictures");
  const VectorMap map = sample();
  exportFloorplan(dir / "plan.png", map);
  exportFloorplan(dir / "plan.svg", map);
  exportFloorplan(dir / "plan.PDF", map);  // extension case does not matter
  EXPECT_EQ(slurp(dir / "plan.png").substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_NE(slurp(dir / "plan.svg").find("<svg"), std::string::npos);
  const std::string pdf = slurp(dir / "plan.PDF");
  EXPECT_EQ(pdf.substr(0, 5), "%PDF-");
  EXPECT_NE(pdf.find("%%EOF"), std::string::npos);
  EXPECT_THROW(exportFloorplan(dir / "plan.docx", map), Error);
  EXPECT_THROW(exportFloorplan(dir / "empty.pdf", VectorMap{}), Error);
  EXPECT_FALSE(fs::exists(dir / "plan.docx"));
  EXPECT_FALSE(fs::exists(dir / "empty.pdf"));
  fs::remove_all(dir);
}

TEST(Export, DxfDeclaresMetres) {
  const fs::path dir = tempDir("dxf");
  exportFloorplan(dir / "plan.dxf", sample());
  const std::string dxf = slurp(dir / "plan.dxf");
  // Header variable $INSUNITS, group code 70, value 6 (metres).
  const std::size_t at = dxf.find("$INSUNITS");
  ASSERT_NE(at, std::string::npos);
  std::istringstream rest(dxf.substr(at + 9));
  std::string code, value;
  rest >> code >> value;
  EXPECT_EQ(code, "70");
  EXPECT_EQ(value, "6");
  EXPECT_NE(dxf.find("GLASS"), std::string::npos);
  EXPECT_NE(dxf.find("WALL"), std::string::npos);
  fs::remove_all(dir);
}

TEST(Export, FloorplanSetWritesEveryDefaultFormat) {
  const fs::path dir = tempDir("set");
  const auto written = writeFloorplanSet(dir / "floorplan", sample());
  ASSERT_EQ(written.size(), 5u);
  for (const std::string ext : {"gpkg", "geojson", "dxf", "svg", "png"})
    EXPECT_TRUE(fs::exists(dir / ("floorplan." + ext))) << ext;
  // An empty map still gives the vector files (readable, empty), but no pictures.
  const auto empty = writeFloorplanSet(dir / "empty", VectorMap{});
  EXPECT_EQ(empty.size(), 3u);
  EXPECT_TRUE(readFloorplan(dir / "empty.gpkg").segments.empty());
  fs::remove_all(dir);
}

TEST(Export, AFloorplanSetThatFailsLeavesNoFileBehind) {
  // The third file cannot be written (as on a full disk): the two before it are removed.
  const fs::path dir = tempDir("set_fails");
  EXPECT_THROW(writeFloorplanSet(dir / "floorplan", sample(), {"geojson", "gpkg", "nosuchformat"}), Error);
  EXPECT_TRUE(fs::is_empty(dir));
  fs::remove_all(dir);
}

TEST(Export, LabelRasterRoundTripIntoVectorize) {
  const fs::path dir = tempDir("raster");
  LabelGrid g = makeLabelGrid(120, 80, 0.05, Vec2(-1.0, 2.0));
  std::fill(g.codes.begin(), g.codes.end(), kCodeEmpty);
  VectorMap truth;
  MapSegment wall;
  wall.a = Vec2(-0.5, 2.5);
  wall.b = Vec2(4.5, 2.5);
  wall.thickness = 0.15;
  MapSegment pane = wall;
  pane.a = Vec2(0.0, 4.5);
  pane.b = Vec2(4.0, 5.0);
  pane.material = Material::Glass;
  pane.thickness = 0.01;
  truth.segments = {wall, pane};
  rasterize(g, truth);
  LabelRaster raster;
  raster.width = g.width;
  raster.height = g.height;
  raster.resolution = g.resolution;
  raster.origin = g.origin;
  raster.codes = g.codes;
  writeLabelRaster(dir / "labels.tif", raster);
  const LabelGrid back = toLabelGrid(readLabelRaster(dir / "labels.tif"));
  EXPECT_EQ(back.codes, g.codes);
  EXPECT_LT((back.origin - g.origin).norm(), 1e-9);
  const VectorizeResult r = vectorize(back);
  const eval::SegmentEvalResult e = eval::evaluateSegments(truth, r.map);
  EXPECT_GT(e.glass.f1, 0.97);
  EXPECT_GT(e.wall.f1, 0.97);
  EXPECT_EQ(e.glass.pred_segments, 1u);
  fs::remove_all(dir);
}

// A bundled scene drawn into a raster (walls at their thickness, glass one cell) vectorises back
// into its own floorplan.
class RasterisedScene : public ::testing::TestWithParam<const char*> {};

TEST_P(RasterisedScene, VectorisesBackToTheFloorplan) {
  const VectorMap truth = readFloorplan(fs::path(GLASSMAP_SOURCE_DIR) / "maps" / GetParam() / "floorplan.geojson");
  const Eigen::AlignedBox2d box = truth.bounds();
  const double res = 0.05;
  const Vec2 origin = box.min() - Vec2::Constant(1.0);
  LabelGrid g = makeLabelGrid(static_cast<int>((box.max().x() - origin.x() + 1.0) / res),
                              static_cast<int>((box.max().y() - origin.y() + 1.0) / res), res, origin);
  std::fill(g.codes.begin(), g.codes.end(), kCodeEmpty);
  rasterize(g, truth);
  const VectorizeResult r = vectorize(g);
  // The desks (outlines 0.08 m thick) are furniture: the walls are the rest of the plan, the
  // clutter layer holds the desks.
  VectorMap structure, desks;
  for (const MapSegment& s : truth.segments)
    (s.material == Material::Wall && s.thickness < 0.1 ? desks : structure).segments.push_back(s);
  const eval::SegmentEvalResult e = eval::evaluateSegments(structure, r.map);
  EXPECT_GT(e.wall.f1, 0.97) << "P " << e.wall.precision << " R " << e.wall.recall;
  EXPECT_GT(eval::evaluateSegments(desks, r.extras.clutter).wall.recall, 0.75);  // short desk ends drop out
  if (e.glass.truth_segments > 0) {
    EXPECT_GT(e.glass.f1, 0.97) << "P " << e.glass.precision << " R " << e.glass.recall;
    EXPECT_LE(e.oversegmentation, 1.0);
    EXPECT_LT(e.glass_angle_error_deg, 1.0);
  } else {
    EXPECT_EQ(e.glass.pred_segments, 0u);
  }
}

INSTANTIATE_TEST_SUITE_P(Maps, RasterisedScene,
                         ::testing::Values("paper-corridor", "glass-corridor", "office-floor", "no-glass"));

}  // namespace
}  // namespace glassmap::vector
