// The clutter layer chosen to explain the returns the walls leave (vector/scan_clutter.hpp).
#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <cmath>
#include <random>

#include "glassmap/vector/scan_clutter.hpp"
#include "vector/synthetic_scans.hpp"

namespace glassmap::vector {
namespace {

MapSegment seg(Vec2 a, Vec2 b) {
  MapSegment s;
  s.a = a;
  s.b = b;
  return s;
}

using synthetic::scanOf;

// A 6 m x 4 m room (the plan's walls).
std::vector<MapSegment> room() {
  return {seg({0, 0}, {6, 0}), seg({6, 0}, {6, 4}), seg({6, 4}, {0, 4}), seg({0, 4}, {0, 0})};
}

// Furniture the plan lacks: a desk front and a shelf.
const MapSegment kDesk = seg({1.5, 0.8}, {3.5, 0.8});
const MapSegment kShelf = seg({5.4, 2.2}, {5.4, 3.4});

// Scans from a row of poses through the room; `person`: someone walking along y = 3.2 ahead of
// the robot (a 0.3 m wide front, 0.25 m further each scan).
LaserLog roomLog(const std::vector<MapSegment>& furniture, bool person = false) {
  std::mt19937_64 rng(11);
  LaserLog log;
  for (int k = 0; k < 24; ++k) {
    std::vector<MapSegment> truth = room();
    truth.insert(truth.end(), furniture.begin(), furniture.end());
    if (person) truth.push_back(seg({0.5 + 0.2 * k, 3.2}, {0.8 + 0.2 * k, 3.2}));
    log.scans.push_back(scanOf(Pose2(1.0 + 0.15 * k, 2.0 + 0.02 * k, 0.1 * k), truth, rng));
  }
  return log;
}

// The labels a map of the room draws: free inside, the walls and the given surfaces occupied.
LabelGrid roomLabels(const std::vector<MapSegment>& surfaces) {
  LabelGrid g = makeLabelGrid(140, 100, 0.05, Vec2(-0.5, -0.5));
  std::fill(g.codes.begin(), g.codes.end(), kCodeEmpty);
  VectorMap solid;
  solid.segments = room();
  solid.segments.insert(solid.segments.end(), surfaces.begin(), surfaces.end());
  rasterize(g, solid, 0.05);
  return g;
}

// The clutter segment nearest to `truth` (its midpoint), or none.
const MapSegment* nearest(const VectorMap& clutter, const MapSegment& truth) {
  const MapSegment* best = nullptr;
  double d_best = 1e9;
  for (const MapSegment& s : clutter.segments) {
    const double d = s.distanceTo(0.5 * (truth.a + truth.b));
    if (d < d_best) d_best = d, best = &s;
  }
  return best;
}

VectorizeResult planWithJunkClutter() {
  VectorizeResult plan;
  plan.map.segments = room();
  // The cells' clutter: outlines of every blob, here ten short pieces nowhere near the furniture.
  for (int k = 0; k < 10; ++k)
    plan.extras.clutter.add(Vec2(0.5 + 0.4 * k, 3.6), Vec2(0.7 + 0.4 * k, 3.6), Material::Wall);
  return plan;
}

TEST(ScanClutter, FurnitureTheWallsMissBecomesClutterAndNothingElse) {
  const LaserLog log = roomLog({kDesk, kShelf});
  const LabelGrid labels = roomLabels({kDesk, kShelf});
  VectorizeResult plan = planWithJunkClutter();
  const ScanClutterStats st = clutterFromScans(plan, log, grid::BeamOptions{}, &labels);
  EXPECT_EQ(st.replaced, 10u);
  // Each piece of furniture is drawn on its returns, along its direction; nothing else is drawn.
  for (const MapSegment& truth : {kDesk, kShelf}) {
    const MapSegment* s = nearest(plan.extras.clutter, truth);
    ASSERT_NE(s, nullptr);
    EXPECT_LT(s->distanceTo(truth.a) + s->distanceTo(truth.b), 0.3) << "end to end within the visible part";
    EXPECT_LT(std::abs(s->direction().dot(Vec2(truth.direction().y(), -truth.direction().x()))), 0.05);
    EXPECT_LT(truth.distanceTo(0.5 * (s->a + s->b)), 0.03);
  }
  EXPECT_LE(plan.extras.clutter.segments.size(), 3u);
  for (const MapSegment& s : plan.extras.clutter.segments)
    EXPECT_LT(std::min(kDesk.distanceTo(0.5 * (s.a + s.b)), kShelf.distanceTo(0.5 * (s.a + s.b))), 0.1);
  EXPECT_LT(st.explained_before, 0.9);
  EXPECT_GT(st.explained_after, 0.98);
  EXPECT_EQ(plan.map.segments.size(), 4u);  // the walls stay as they are
}

TEST(ScanClutter, APersonWalkingByLeavesNoSegmentWhereTheMapSawFreeSpace) {
  const LaserLog log = roomLog({kDesk}, true);
  const LabelGrid labels = roomLabels({kDesk});  // the person's path is free space in the map
  auto onPath = [](const MapSegment& s) { return std::abs(0.5 * (s.a.y() + s.b.y()) - 3.2) < 0.1; };
  VectorizeResult plan = planWithJunkClutter();
  clutterFromScans(plan, log, grid::BeamOptions{}, &labels);
  ASSERT_NE(nearest(plan.extras.clutter, kDesk), nullptr);
  for (const MapSegment& s : plan.extras.clutter.segments) EXPECT_FALSE(onPath(s)) << s.a.transpose();
  // Without the map's free space the trail of returns is a line like any other.
  VectorizeResult blind = planWithJunkClutter();
  clutterFromScans(blind, log, grid::BeamOptions{}, nullptr);
  EXPECT_TRUE(std::any_of(blind.extras.clutter.segments.begin(), blind.extras.clutter.segments.end(), onPath));
}

TEST(ScanClutter, ASegmentDoesNotRunThroughFreeSpace) {
  // Two cabinets in a row 0.3 m apart (less than max_gap): the map saw the gap free, so they are
  // two segments; without the map one line spans both.
  const MapSegment left = seg({1.0, 0.8}, {2.5, 0.8}), right = seg({2.8, 0.8}, {4.3, 0.8});
  const LaserLog log = roomLog({left, right});
  const LabelGrid labels = roomLabels({left, right});
  auto spans_gap = [](const VectorMap& clutter) {
    return std::any_of(clutter.segments.begin(), clutter.segments.end(),
                       [](const MapSegment& s) { return s.distanceTo(Vec2(2.65, 0.8)) < 0.05; });
  };
  VectorizeResult plan = planWithJunkClutter();
  clutterFromScans(plan, log, grid::BeamOptions{}, &labels);
  EXPECT_FALSE(spans_gap(plan.extras.clutter));
  EXPECT_NE(nearest(plan.extras.clutter, left), nearest(plan.extras.clutter, right));
  VectorizeResult blind = planWithJunkClutter();
  clutterFromScans(blind, log, grid::BeamOptions{}, nullptr);
  EXPECT_TRUE(spans_gap(blind.extras.clutter));
}

TEST(ScanClutter, ASegmentMustExplainItsShareOfTheReturns) {
  const LaserLog log = roomLog({kDesk, kShelf});
  const LabelGrid labels = roomLabels({kDesk, kShelf});
  // No single piece explains a fifth of all the returns: nothing is drawn, the cells' clutter goes.
  ScanClutterOptions strict;
  strict.min_share = 0.2;
  VectorizeResult plan = planWithJunkClutter();
  const ScanClutterStats st = clutterFromScans(plan, log, grid::BeamOptions{}, &labels, {}, strict);
  EXPECT_EQ(st.added, 0u);
  EXPECT_TRUE(plan.extras.clutter.segments.empty());
  EXPECT_NEAR(st.explained_after, st.explained_walls, 1e-12);
  // Off: the cells' clutter stays.
  ScanClutterOptions off;
  off.enabled = false;
  VectorizeResult kept = planWithJunkClutter();
  clutterFromScans(kept, log, grid::BeamOptions{}, &labels, {}, off);
  EXPECT_EQ(kept.extras.clutter.segments.size(), 10u);
}

TEST(ScanClutter, TheLinesNeverExplainLessThanTheCellsPiecesDid) {
  // The cells drew the desk and the shelf (in two pieces each) and a piece nowhere; no line
  // explains a fifth of the returns, so the pieces with returns come back until the plan
  // explains what it did before; the stray piece does not.
  const LaserLog log = roomLog({kDesk, kShelf});
  const LabelGrid labels = roomLabels({kDesk, kShelf});
  VectorizeResult plan;
  plan.map.segments = room();
  plan.extras.clutter.add(Vec2(1.5, 0.8), Vec2(2.5, 0.8), Material::Wall);
  plan.extras.clutter.add(Vec2(2.5, 0.8), Vec2(3.5, 0.8), Material::Wall);
  plan.extras.clutter.add(Vec2(5.4, 2.2), Vec2(5.4, 2.8), Material::Wall);
  plan.extras.clutter.add(Vec2(5.4, 2.8), Vec2(5.4, 3.4), Material::Wall);
  plan.extras.clutter.add(Vec2(0.5, 3.6), Vec2(0.7, 3.6), Material::Wall);
  ScanClutterOptions strict;
  strict.min_share = 0.2;
  const ScanClutterStats st = clutterFromScans(plan, log, grid::BeamOptions{}, &labels, {}, strict);
  EXPECT_EQ(st.added, 0u);
  EXPECT_EQ(st.restored, 4u);
  EXPECT_EQ(st.replaced, 1u);
  EXPECT_GT(st.explained_before, st.explained_walls + 0.05);
  EXPECT_GE(st.explained_after, st.explained_before - 1e-3);  // up to the 2 cm merge of the returns
  ASSERT_EQ(plan.extras.clutter.segments.size(), 4u);
  for (const MapSegment& s : plan.extras.clutter.segments) EXPECT_GT(s.a.y(), 0.5);  // not the stray piece
  // With the default share the lines explain more than the pieces: none comes back.
  VectorizeResult lines;
  lines.map.segments = room();
  lines.extras.clutter = plan.extras.clutter;
  const ScanClutterStats st2 = clutterFromScans(lines, log, grid::BeamOptions{}, &labels);
  EXPECT_EQ(st2.restored, 0u);
  EXPECT_GE(st2.added, 2u);
  EXPECT_GE(st2.explained_after, st2.explained_before);
}

TEST(ScanClutter, TheLabelsMayLieInAFrameOfTheirOwn) {
  // A ROS map whose origin is rotated: the labels in their own frame, placed by a pose.
  const LaserLog log = roomLog({kDesk}, true);
  LabelGrid labels = roomLabels({kDesk});
  const Pose2 grid_pose(Vec2(3.0, -1.0), 0.5);  // the grid's frame in the map frame
  // Re-express the grid: the same cells, now in a frame at grid_pose (nearest-cell resampling).
  LabelGrid rotated = makeLabelGrid(300, 300, 0.05, Vec2(-6.0, -4.0));  // covers the room
  for (int y = 0; y < rotated.height; ++y)
    for (int x = 0; x < rotated.width; ++x) {
      const Vec2 p = grid_pose * rotated.center(x, y);  // map frame
      const Vec2 q = (p - labels.origin) / labels.resolution;
      if (q.x() >= 0 && q.y() >= 0 && q.x() < labels.width && q.y() < labels.height)
        rotated.codes[static_cast<std::size_t>(y) * rotated.width + x] =
            labels.code(static_cast<int>(q.x()), static_cast<int>(q.y()));
    }
  VectorizeResult a = planWithJunkClutter(), b = planWithJunkClutter();
  clutterFromScans(a, log, grid::BeamOptions{}, &labels);
  clutterFromScans(b, log, grid::BeamOptions{}, &rotated, grid_pose);
  ASSERT_EQ(a.extras.clutter.segments.size(), b.extras.clutter.segments.size());
  for (std::size_t k = 0; k < a.extras.clutter.segments.size(); ++k)
    EXPECT_LT((a.extras.clutter.segments[k].a - b.extras.clutter.segments[k].a).norm(), 0.05);
}

TEST(ScanClutter, TheSameOnAnyNumberOfThreads) {
  const LaserLog log = roomLog({kDesk, kShelf}, true);
  const LabelGrid labels = roomLabels({kDesk, kShelf});
  VectorizeResult many = planWithJunkClutter(), one = planWithJunkClutter();
  clutterFromScans(many, log, grid::BeamOptions{}, &labels);
  {
    tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
    clutterFromScans(one, log, grid::BeamOptions{}, &labels);
  }
  ASSERT_EQ(many.extras.clutter.segments.size(), one.extras.clutter.segments.size());
  for (std::size_t k = 0; k < many.extras.clutter.segments.size(); ++k) {
    EXPECT_EQ(many.extras.clutter.segments[k].a, one.extras.clutter.segments[k].a);
    EXPECT_EQ(many.extras.clutter.segments[k].b, one.extras.clutter.segments[k].b);
  }
}

}  // namespace
}  // namespace glassmap::vector
