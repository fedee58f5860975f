// Two steps around the fit: the cells put back in line with the fitted panes
// (pruneUnfittedGlass), and a wall seen from one side placed on its observed face.
#include <gtest/gtest.h>

#include <cmath>

#include "glassmap/core/labels.hpp"
#include "glassmap/vector/from_evidence.hpp"
#include "glassmap/vector/vectorize.hpp"

namespace glassmap::vector {
namespace {

glass::CellEvidence blankEvidence(int w, int h) {
  glass::CellEvidence e;
  e.geometry.resolution = 0.05;
  e.geometry.origin = Vec2::Zero();
  e.geometry.width = w;
  e.geometry.height = h;
  e.label.assign(static_cast<std::size_t>(w) * h, static_cast<std::uint8_t>(kEmpty));
  return e;
}

TEST(PruneUnfittedGlass, CellsOffEveryPaneTakeTheirBestOtherLabel) {
  glass::CellEvidence e = blankEvidence(100, 100);
  const auto& g = e.geometry;
  // A pane along y = 2.525 (row 50), x 1..4 m, normal along y (bin 18 of 36).
  for (int x = 20; x < 80; ++x) e.label[g.index(x, 50)] = static_cast<std::uint8_t>(glassLabel(18));
  // An arc of "glass" cells where a person walked by, far from the pane.
  for (int x = 30; x < 36; ++x) e.label[g.index(x, 20)] = static_cast<std::uint8_t>(glassLabel(18));
  // One arc cell has costs that prefer OCC to EMP; it must become OCC.
  e.cells = {static_cast<std::uint32_t>(g.index(31, 20))};
  e.cost.assign(static_cast<std::size_t>(e.num_labels), glass::CellEvidence::kMaxCost);
  e.cost[kOccupied] = 2.0f;
  e.cost[kEmpty] = 3.0f;
  e.cost[glassLabel(18)] = 0.5f;

  VectorMap plan;
  plan.add({1.0, 2.525}, {4.0, 2.525}, Material::Glass);
  plan.add({1.0, 1.025}, {4.0, 1.025}, Material::Wall);  // a wall segment explains no glass

  EXPECT_EQ(pruneUnfittedGlass(e, plan), 6u);
  for (int x = 20; x < 80; ++x) EXPECT_TRUE(isGlass(e.label[g.index(x, 50)])) << x;
  EXPECT_EQ(e.label[g.index(31, 20)], kOccupied);
  for (int x : {30, 32, 33, 34, 35}) EXPECT_EQ(e.label[g.index(x, 20)], kEmpty) << x;
  EXPECT_EQ(pruneUnfittedGlass(e, plan), 0u);  // idempotent
  EXPECT_EQ(pruneUnfittedGlass(e, VectorMap{}), 60u);
}

TEST(FillFittedGlass, TheGapsOfAFaintPaneBecomeGlassAndWallsStay) {
  glass::CellEvidence e = blankEvidence(100, 100);
  const auto& g = e.geometry;
  // A faint pane along row 50 (y = 2.525), x 1..4 m: one cell in four drawn, normal along y.
  for (int x = 20; x < 80; x += 4) e.label[g.index(x, 50)] = static_cast<std::uint8_t>(glassLabel(18));
  e.label[g.index(41, 50)] = static_cast<std::uint8_t>(kOccupied);  // a mullion
  e.label[g.index(42, 50)] = kUnknown;                              // never seen
  VectorMap plan;
  plan.add({1.0, 2.525}, {4.0, 2.525}, Material::Glass);
  plan.add({1.0, 1.025}, {4.0, 1.025}, Material::Wall);  // walls fill nothing
  // A pane at 45 deg from (1.01, 3.5) to (2.01, 4.5): a 4-connected staircase of cells, normal at
  // 135 deg.
  plan.add({1.01, 3.5}, {2.01, 4.5}, Material::Glass);

  const std::vector<std::uint8_t> before = e.label;
  const std::size_t filled = fillFittedGlass(e, plan);
  std::size_t changed = 0;
  for (std::size_t i = 0; i < before.size(); ++i) changed += before[i] != e.label[i];
  EXPECT_EQ(filled, changed);
  for (int x = 20; x < 80; ++x) {
    if (x == 41) continue;
    EXPECT_EQ(e.label[g.index(x, 50)], glassLabel(18)) << x;
  }
  EXPECT_EQ(e.label[g.index(41, 50)], kOccupied);
  for (int x = 20; x < 80; ++x) EXPECT_EQ(e.label[g.index(x, 20)], kEmpty) << x;
  // The diagonal: binned at 135 deg (bin 27), each cell followed by the one to its right or above
  // but the last.
  int diagonal = 0, ends = 0;
  for (int y = 65; y < 95; ++y)
    for (int x = 15; x < 45; ++x) {
      const int l = e.label[g.index(x, y)];
      if (!isGlass(l)) continue;
      ++diagonal;
      EXPECT_EQ(glassBin(l), 27) << x << " " << y;
      ends += !isGlass(e.label[g.index(x + 1, y)]) && !isGlass(e.label[g.index(x, y + 1)]);
    }
  EXPECT_GE(diagonal, 40);
  EXPECT_LE(diagonal, 41);
  EXPECT_EQ(ends, 1);
  EXPECT_GE(filled, 60u - 15u - 1u + static_cast<std::size_t>(diagonal));  // and the cells the ends touch
  EXPECT_EQ(fillFittedGlass(e, plan), 0u);                                 // idempotent
  EXPECT_EQ(fillFittedGlass(e, VectorMap{}), 0u);
}

// A wall band four cells thick (y 2.40 .. 2.60). Seen from below only, the wall lies on the edge
// of free space; with free space on both sides it stays in the middle.
double wallLineY(bool free_above, bool align = true) {
  LabelGrid g = makeLabelGrid(120, 100, 0.05);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      std::uint8_t code = y < 48 ? kCodeEmpty : y < 52 ? kCodeOccupied : (free_above ? kCodeEmpty : kCodeUnknown);
      g.codes[static_cast<std::size_t>(y) * g.width + x] = code;
    }
  VectorizeOptions o;
  o.face_align = align;
  const VectorizeResult r = vectorize(g, o);
  EXPECT_EQ(r.map.count(Material::Wall), 1u);
  for (const MapSegment& s : r.map.segments)
    if (s.material == Material::Wall) return 0.5 * (s.a.y() + s.b.y());
  return NAN;
}

TEST(Vectorize, OneSidedWallLiesOnItsObservedFace) {
  EXPECT_NEAR(wallLineY(false), 2.425, 0.03);
  EXPECT_NEAR(wallLineY(true), 2.50, 0.03);
  EXPECT_NEAR(wallLineY(false, false), 2.50, 0.03);  // without the step: the middle of the band
}

}  // namespace
}  // namespace glassmap::vector
