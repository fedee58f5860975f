// Segment-level scores on hand-made floorplans.
#include <gtest/gtest.h>

#include <cmath>

#include "glassmap/core/angles.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/eval/segments.hpp"

namespace glassmap::eval {
namespace {

MapSegment seg(double ax, double ay, double bx, double by, Material m) {
  MapSegment s;
  s.a = Vec2(ax, ay);
  s.b = Vec2(bx, by);
  s.material = m;
  return s;
}

VectorMap office() {
  VectorMap m;
  m.segments = {seg(0, 0, 10, 0, Material::Wall), seg(10, 0, 10, 6, Material::Wall), seg(0, 6, 10, 6, Material::Wall),
                seg(0, 0, 0, 6, Material::Wall),  seg(3, 3, 7, 3, Material::Glass),  seg(8, 1, 9, 4, Material::Glass)};
  return m;
}

VectorMap shifted(VectorMap m, const Vec2& d) {
  for (MapSegment& s : m.segments) s.a += d, s.b += d;
  return m;
}

TEST(EvalSegments, IdenticalMapsScoreOne) {
  const SegmentEvalResult r = evaluateSegments(office(), office());
  EXPECT_DOUBLE_EQ(r.glass.f1, 1.0);
  EXPECT_DOUBLE_EQ(r.wall.f1, 1.0);
  EXPECT_NEAR(r.glass.truth_length, 4.0 + std::sqrt(10.0), 1e-9);
  EXPECT_NEAR(r.wall.truth_length, 32.0, 1e-9);
  EXPECT_NEAR(r.glass_angle_error_deg, 0.0, 1e-9);
  EXPECT_DOUBLE_EQ(r.oversegmentation, 1.0);
  EXPECT_EQ(r.panes_found, 2u);
  EXPECT_DOUBLE_EQ(r.segments_per_found_pane, 1.0);
  EXPECT_DOUBLE_EQ(r.longest_false_glass, 0.0);
}

TEST(EvalSegments, ShiftBeyondToleranceScoresZero) {
  // Shift by (0.12, -0.12) m: every segment, the slanted pane too, moves more than 0.10 m sideways.
  const SegmentEvalResult r = evaluateSegments(office(), shifted(office(), Vec2(0.12, -0.12)));
  EXPECT_LT(r.wall.f1, 0.03);  // only the samples near corners, where perpendicular walls meet, match
  EXPECT_DOUBLE_EQ(r.glass.f1, 0.0);
  EXPECT_EQ(r.panes_found, 0u);
  EXPECT_NEAR(r.longest_false_glass, 4.0, 0.03);
}

TEST(EvalSegments, ShiftWithinToleranceScoresOne) {
  const SegmentEvalResult r = evaluateSegments(office(), shifted(office(), Vec2(0.0, 0.05)));
  EXPECT_DOUBLE_EQ(r.glass.f1, 1.0);
  // Vertical walls shifted along themselves overhang by 5 cm, which lies within the tolerance.
  EXPECT_DOUBLE_EQ(r.wall.f1, 1.0);
}

TEST(EvalSegments, HalfAPaneIsHalfTheRecallAndFullPrecision) {
  VectorMap truth, pred;
  truth.segments = {seg(0, 0, 4, 0, Material::Glass)};
  pred.segments = {seg(0, 0, 2, 0, Material::Glass)};
  const SegmentEvalResult r = evaluateSegments(truth, pred);
  EXPECT_DOUBLE_EQ(r.glass.precision, 1.0);
  EXPECT_NEAR(r.glass.recall, 0.5 + 0.1 / 4.0, 0.006);  // samples within 0.10 m past the end count
  EXPECT_DOUBLE_EQ(r.wall.f1, 1.0);                     // no walls on either side
}

TEST(EvalSegments, WrongMaterialDoesNotMatch) {
  VectorMap truth, pred;
  truth.segments = {seg(0, 0, 4, 0, Material::Wall)};
  pred.segments = {seg(0, 0, 4, 0, Material::Glass)};
  const SegmentEvalResult r = evaluateSegments(truth, pred);
  EXPECT_DOUBLE_EQ(r.glass.precision, 0.0);
  EXPECT_DOUBLE_EQ(r.glass.recall, 1.0);  // no true glass
  EXPECT_DOUBLE_EQ(r.glass.f1, 0.0);
  EXPECT_DOUBLE_EQ(r.wall.recall, 0.0);
  EXPECT_DOUBLE_EQ(r.wall.f1, 0.0);
  EXPECT_NEAR(r.longest_false_glass, 4.0, 1e-9);
}

TEST(EvalSegments, FragmentsAndAngleError) {
  VectorMap truth, pred;
  truth.segments = {seg(0, 0, 6, 0, Material::Glass)};
  // Three pieces, the last tilted by 1 degree about its start.
  const double a = deg2rad(1.0);
  pred.segments = {seg(0, 0, 2, 0, Material::Glass), seg(2, 0, 4, 0, Material::Glass),
                   seg(4, 0, 4 + 2 * std::cos(a), 2 * std::sin(a), Material::Glass)};
  const SegmentEvalResult r = evaluateSegments(truth, pred);
  EXPECT_DOUBLE_EQ(r.oversegmentation, 3.0);
  EXPECT_EQ(r.panes_found, 1u);
  EXPECT_DOUBLE_EQ(r.segments_per_found_pane, 3.0);
  EXPECT_NEAR(r.glass_angle_error_deg, 1.0 / 3.0, 1e-6);
  EXPECT_NEAR(r.glass.f1, 1.0, 1e-9);
}

TEST(EvalSegments, EmptyPredictionAndBadOptions) {
  const SegmentEvalResult r = evaluateSegments(office(), VectorMap{});
  EXPECT_DOUBLE_EQ(r.glass.precision, 1.0);
  EXPECT_DOUBLE_EQ(r.glass.recall, 0.0);
  EXPECT_DOUBLE_EQ(r.glass.f1, 0.0);
  EXPECT_DOUBLE_EQ(r.oversegmentation, 0.0);
  SegmentEvalOptions bad;
  bad.sample_step = 0;
  EXPECT_THROW(evaluateSegments(office(), office(), bad), Error);
}

}  // namespace
}  // namespace glassmap::eval
