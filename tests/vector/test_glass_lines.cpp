// Glass panes from sparse glass cells (vector/glass_lines.cpp): a laser with a narrow direct-return
// lobe leaves one pane cell in three or four; the voting finds the pane at every angle, cuts it
// only at gaps its own density makes unlikely, and leaves scattered glass cells alone.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "glassmap/core/angles.hpp"
#include "glassmap/vector/vectorize.hpp"

namespace glassmap::vector {
namespace {

// A grid of empty cells with every `step`-th cell of a pane from a to b set to glass (its normal
// label, turned by `label_bias_deg`), starting at cell `phase`.
void drawSparsePane(LabelGrid& g, const Vec2& a, const Vec2& b, int step, int phase = 0, double label_bias_deg = 0.0) {
  const Vec2 d = (b - a).normalized();
  const double normal = std::atan2(d.x(), -d.y()) + deg2rad(label_bias_deg);
  const std::uint8_t code = glassCodeOf(normal, g.angle_bin_deg);
  const int n = static_cast<int>((b - a).norm() / g.resolution);
  for (int k = phase; k <= n; k += step) {
    const Vec2 p = a + (k * g.resolution) * d;
    const int x = static_cast<int>(std::floor(p.x() / g.resolution));
    const int y = static_cast<int>(std::floor(p.y() / g.resolution));
    if (x >= 0 && y >= 0 && x < g.width && y < g.height) g.codes[static_cast<std::size_t>(y) * g.width + x] = code;
  }
}

LabelGrid emptyGrid(double w, double h) {
  LabelGrid g = makeLabelGrid(static_cast<int>(w / 0.05), static_cast<int>(h / 0.05), 0.05);
  std::fill(g.codes.begin(), g.codes.end(), kCodeEmpty);
  return g;
}

std::vector<MapSegment> glassOf(const VectorMap& map) {
  std::vector<MapSegment> out;
  for (const MapSegment& s : map.segments)
    if (s.material == Material::Glass) out.push_back(s);
  return out;
}

double directionErrorDeg(const MapSegment& s, double expected_rad) {
  const double a = std::atan2(s.b.y() - s.a.y(), s.b.x() - s.a.x());
  return rad2deg(std::abs(std::remainder(a - expected_rad, kPi)));
}

class SparsePane : public ::testing::TestWithParam<double> {};

TEST_P(SparsePane, OneCellInThreeIsOnePaneAtAnyAngle) {
  const double angle = deg2rad(GetParam());
  const Vec2 centre(4.0, 4.0), d(std::cos(angle), std::sin(angle));
  const Vec2 a = centre - 1.5 * d, b = centre + 1.5 * d;
  LabelGrid g = emptyGrid(8.0, 8.0);
  drawSparsePane(g, a, b, 3);
  const VectorizeResult r = vectorize(g);
  const auto glass = glassOf(r.map);
  ASSERT_EQ(glass.size(), 1u) << "pane at " << GetParam() << " deg";
  EXPECT_LT(directionErrorDeg(glass[0], angle), 1.5);
  EXPECT_NEAR((glass[0].b - glass[0].a).norm(), 3.0, 0.2);
  EXPECT_LT(std::abs((glass[0].a - centre).dot(Vec2(-d.y(), d.x()))), 0.05);
}

INSTANTIATE_TEST_SUITE_P(Angles, SparsePane, ::testing::Values(0.0, 12.0, 25.0, 45.0, 65.0, 90.0, 115.0, 135.0, 160.0));

TEST(GlassLines, RegionGrowingAloneLosesTheSparsePane) {
  LabelGrid g = emptyGrid(8.0, 8.0);
  drawSparsePane(g, Vec2(2.5, 4.0), Vec2(5.5, 4.0), 3);
  VectorizeOptions o;
  o.glass_voting = false;
  EXPECT_TRUE(glassOf(vectorize(g, o).map).empty());
  EXPECT_EQ(glassOf(vectorize(g).map).size(), 1u);
}

TEST(GlassLines, ADoorGapInADensePaneStaysOpenButASparsePaneIsNotCut) {
  LabelGrid g = emptyGrid(10.0, 6.0);
  // Dense pane with a 0.9 m door: two segments.
  drawSparsePane(g, Vec2(1.0, 2.0), Vec2(3.0, 2.0), 1);
  drawSparsePane(g, Vec2(3.9, 2.0), Vec2(6.0, 2.0), 1);
  // Sparse pane (one cell in four, gaps of 0.15 m) over 4 m: one segment.
  drawSparsePane(g, Vec2(1.0, 4.5), Vec2(5.0, 4.5), 4);
  const auto glass = glassOf(vectorize(g).map);
  int low = 0, high = 0;
  for (const MapSegment& s : glass) ++(s.a.y() < 3.0 ? low : high);
  EXPECT_EQ(low, 2);
  EXPECT_EQ(high, 1);
}

// The end of a pane seen only obliquely: a short run of cells whose normal labels are all biased
// alike (a wide lobe returns off the normal, the MRF makes the labels agree) is too short to stand
// out alone among every line of the grid, but continues the pane: it joins it. Across a gap seen
// free (a door), the same run stays out.
TEST(GlassLines, AShortBiasedTailContinuesItsPane) {
  const double angle = deg2rad(8.0);
  const Vec2 d(std::cos(angle), std::sin(angle)), start(1.0, 3.0);
  LabelGrid g = emptyGrid(10.0, 6.0);
  drawSparsePane(g, start, start + 3.0 * d, 1);                     // the pane seen well
  drawSparsePane(g, start + 3.2 * d, start + 3.6 * d, 1, 0, 18.0);  // its tail, labels 18 deg off
  const auto glass = glassOf(vectorize(g).map);
  ASSERT_EQ(glass.size(), 1u);
  const double far_end = std::max((glass[0].a - start).dot(d), (glass[0].b - start).dot(d));
  EXPECT_GT(far_end, 3.5) << "the tail was not joined";
  EXPECT_LT(directionErrorDeg(glass[0], angle), 1.5);

  // The same tail 0.6 m on, beyond a gap seen free: a door, not an unseen stretch of the pane.
  LabelGrid h = emptyGrid(10.0, 6.0);
  drawSparsePane(h, start, start + 3.0 * d, 1);
  drawSparsePane(h, start + 3.6 * d, start + 4.0 * d, 1, 0, 18.0);
  for (const MapSegment& s : glassOf(vectorize(h).map))
    EXPECT_LT(std::max((s.a - start).dot(d), (s.b - start).dot(d)), 3.1) << "joined across a door";
}

TEST(GlassLines, ScatteredGlassCellsMakeNoPane) {
  LabelGrid g = emptyGrid(10.0, 10.0);
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> cell(0, static_cast<int>(g.cells()) - 1), bin(0, 35);
  for (int i = 0; i < 300; ++i)  // 300 glass cells of random angle over 100 m^2
    g.codes[static_cast<std::size_t>(cell(rng))] = static_cast<std::uint8_t>(kCodeFirstGlass + bin(rng));
  EXPECT_TRUE(glassOf(vectorize(g).map).empty());
}

}  // namespace
}  // namespace glassmap::vector
