// Tests of the cell evaluation on hand-made rasters.
#include <gtest/gtest.h>

#include <cmath>

#include "glassmap/core/labels.hpp"
#include "glassmap/eval/cells.hpp"

namespace glassmap::eval {
namespace {

grid::GridGeometry grid20() {
  grid::GridGeometry g;
  g.resolution = 0.1;
  g.origin = Vec2(0.0, 0.0);
  g.width = 20;
  g.height = 20;
  return g;
}

// A vertical pane through the middle of column 10, rows 5..14 (normal along x: 0 deg, bin 0).
VectorMap pane() {
  VectorMap m;
  MapSegment s;
  s.a = Vec2(1.05, 0.55);
  s.b = Vec2(1.05, 1.45);
  s.material = Material::Glass;
  m.segments.push_back(s);
  MapSegment wall;
  wall.a = Vec2(0.05, 0.05);
  wall.b = Vec2(1.95, 0.05);
  m.segments.push_back(wall);  // walls are no glass truth
  return m;
}

TEST(Rasterise, MarksCellsOfGlassSegmentsWithTheirNormal) {
  const auto g = grid20();
  std::size_t outside = 7;
  const auto n = rasteriseGlass(pane(), g, &outside);
  EXPECT_EQ(outside, 0U);
  int count = 0;
  for (int y = 0; y < 20; ++y) {
    for (int x = 0; x < 20; ++x) {
      const float v = n[g.index(x, y)];
      if (std::isnan(v)) continue;
      ++count;
      EXPECT_EQ(x, 10);
      EXPECT_NEAR(v, 0.0, 1e-6);
    }
  }
  EXPECT_EQ(count, 10);
  // A segment sticking out of the grid counts its outer cells.
  VectorMap m = pane();
  m.segments[0].b = Vec2(1.05, 2.45);
  rasteriseGlass(m, g, &outside);
  EXPECT_EQ(outside, 5U);
}

TEST(EvaluateCells, PerfectMapScoresOne) {
  const auto g = grid20();
  std::vector<std::uint8_t> labels(g.cells(), kEmpty);
  for (int y = 5; y < 15; ++y) labels[g.index(10, y)] = glassLabel(0);
  const CellEvalResult r = evaluateCells(pane(), g, labels);
  EXPECT_EQ(r.ground_truth, 10U);
  EXPECT_EQ(r.predicted, 10U);
  EXPECT_EQ(r.exact_found, 10U);
  EXPECT_EQ(r.found, 10U);
  EXPECT_EQ(r.false_positives, 0U);
  EXPECT_EQ(r.not_found, 0U);
  EXPECT_DOUBLE_EQ(r.exact.f1, 1.0);
  EXPECT_DOUBLE_EQ(r.tolerant.f1, 1.0);
  EXPECT_DOUBLE_EQ(r.mean_angle_error_deg, 0.0);
}

TEST(EvaluateCells, CountsTableIColumns) {
  const auto g = grid20();
  std::vector<std::uint8_t> labels(g.cells(), kEmpty);
  labels[g.index(10, 5)] = glassLabel(0);   // exact, right angle
  labels[g.index(10, 6)] = glassLabel(2);   // exact, 10 deg off
  labels[g.index(12, 9)] = glassLabel(35);  // 2 cells off: displaced find of (10, 9), 5 deg off
  labels[g.index(13, 12)] = glassLabel(0);  // 3 cells off: false positive
  labels[g.index(2, 2)] = glassLabel(0);    // false positive
  labels[g.index(10, 14)] = kOccupied;      // not glass: not found
  const CellEvalResult r = evaluateCells(pane(), g, labels);
  EXPECT_EQ(r.ground_truth, 10U);
  EXPECT_EQ(r.predicted, 5U);
  EXPECT_EQ(r.exact_found, 2U);
  // (12, 9) is within 2 cells of rows 7..11 of column 10: five truth cells found displaced.
  EXPECT_EQ(r.found_displaced, 5U);
  EXPECT_EQ(r.not_found, 3U);
  EXPECT_EQ(r.found, 3U);
  EXPECT_EQ(r.false_positives, 2U);
  EXPECT_DOUBLE_EQ(r.exact.precision, 2.0 / 5.0);
  EXPECT_DOUBLE_EQ(r.exact.recall, 2.0 / 10.0);
  EXPECT_NEAR(r.exact.f1, 2 * 0.4 * 0.2 / 0.6, 1e-12);
  EXPECT_DOUBLE_EQ(r.tolerant.precision, 3.0 / 5.0);
  EXPECT_DOUBLE_EQ(r.tolerant.recall, 7.0 / 10.0);
  EXPECT_DOUBLE_EQ(r.paper_recall, 0.3);
  EXPECT_DOUBLE_EQ(r.paper_precision, 0.2);
  EXPECT_EQ(r.angle_cells, 3U);
  EXPECT_NEAR(r.mean_angle_error_deg, (0.0 + 10.0 + 5.0) / 3.0, 1e-9);
  // Zero tolerance: displaced finds vanish.
  CellEvalOptions o;
  o.tolerance_cells = 0;
  const CellEvalResult r0 = evaluateCells(pane(), g, labels, 36, o);
  EXPECT_EQ(r0.found_displaced, 0U);
  EXPECT_EQ(r0.found, 2U);
  EXPECT_EQ(r0.false_positives, 3U);
}

TEST(EvaluateCells, EmptyPredictionAndBadSize) {
  const auto g = grid20();
  std::vector<std::uint8_t> labels(g.cells(), kUnknown);
  const CellEvalResult r = evaluateCells(pane(), g, labels);
  EXPECT_EQ(r.predicted, 0U);
  EXPECT_EQ(r.not_found, 10U);
  EXPECT_DOUBLE_EQ(r.tolerant.f1, 0.0);
  labels.pop_back();
  EXPECT_ANY_THROW(evaluateCells(pane(), g, labels));
}

}  // namespace
}  // namespace glassmap::eval
