// The vectorizer's finer rules are options with units: each one changes the result the way its
// documentation says.
#include <gtest/gtest.h>

#include <cmath>

#include "glassmap/core/angles.hpp"
#include "glassmap/vector/label_grid.hpp"
#include "glassmap/vector/vectorize.hpp"

namespace glassmap::vector {
namespace {

// A free room of w x h m (every cell empty) with the plan's segments drawn in.
LabelGrid drawn(const VectorMap& plan, double w, double h) {
  LabelGrid g = makeLabelGrid(static_cast<int>(w / 0.05), static_cast<int>(h / 0.05), 0.05, Vec2(-1, -1));
  for (auto& c : g.codes) c = kCodeEmpty;
  rasterize(g, plan);
  return g;
}

double wallLength(const VectorizeResult& r) {
  double len = 0;
  for (const MapSegment& s : r.map.segments)
    if (s.material == Material::Wall) len += s.length();
  return len;
}

TEST(VectorizeOptions, EndMarginSetsHowFarSegmentsReachPastTheirCells) {
  VectorMap plan;
  plan.add({0, 0}, {4, 0}, Material::Wall).thickness = 0.1;
  const LabelGrid g = drawn(plan, 6, 2);
  VectorizeOptions o;
  o.regularize = false;
  const double base = wallLength(vectorize(g, o));
  o.end_margin_cells = 2.5;  // two cells more at each end
  const double longer = wallLength(vectorize(g, o));
  EXPECT_NEAR(base, 4.0 + 0.05, 0.06);
  EXPECT_NEAR(longer - base, 4 * 0.05, 1e-6);
}

TEST(VectorizeOptions, CornerAngleDecidesWhichEndsSnap) {
  // A wall meeting another at 20 degrees, its end 0.25 m short of their lines' intersection.
  VectorMap plan;
  plan.add({0, 0}, {5, 0}, Material::Wall).thickness = 0.1;
  const double a = deg2rad(20.0);
  const Vec2 start(5.25, 0.09);
  plan.add(start, start + 4.0 * Vec2(std::cos(a), std::sin(a)), Material::Wall).thickness = 0.1;
  const LabelGrid g = drawn(plan, 11, 4);
  VectorizeOptions o;
  o.regularize = false;
  const VectorizeResult steep_only = vectorize(g, o);  // default: 30 degrees or more
  EXPECT_EQ(steep_only.stats.corners, 0u);
  o.corner_min_angle_deg = 15.0;
  const VectorizeResult shallow = vectorize(g, o);
  EXPECT_GE(shallow.stats.corners, 1u);
  // The angled wall now starts on the first wall's line.
  bool joined = false;
  for (const MapSegment& s : shallow.map.segments)
    if (std::abs(s.a.y()) < 0.03 && s.b.y() > 1.0) joined = true;
  EXPECT_TRUE(joined);
}

TEST(VectorizeOptions, MinRegionCellsDropsSmallRegions) {
  VectorMap plan;
  plan.add({0, 0}, {4, 0}, Material::Wall).thickness = 0.1;
  plan.add({0, 1.5}, {0.6, 1.5}, Material::Wall).thickness = 0.05;  // a short stub: 12 cells
  const LabelGrid g = drawn(plan, 6, 3);
  VectorizeOptions o;
  o.regularize = false;
  o.structure.enabled = false;  // the stub alone would be clutter
  EXPECT_EQ(vectorize(g, o).map.segments.size(), 2u);
  o.min_region_cells = 20;
  EXPECT_EQ(vectorize(g, o).map.segments.size(), 1u);
}

}  // namespace
}  // namespace glassmap::vector
