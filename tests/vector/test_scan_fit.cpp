// Walls moved onto the returns they were mapped from (vector/scan_fit.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "glassmap/vector/scan_fit.hpp"
#include "vector/synthetic_scans.hpp"

namespace glassmap::vector {
namespace {

MapSegment seg(Vec2 a, Vec2 b, Material m = Material::Wall) {
  MapSegment s;
  s.a = a;
  s.b = b;
  s.material = m;
  return s;
}

using synthetic::scanOf;

// Scans from a row of poses through a 6 m x 4 m room whose walls are `truth`.
LaserLog roomLog(const std::vector<MapSegment>& truth) {
  std::mt19937_64 rng(7);
  LaserLog log;
  for (int k = 0; k < 20; ++k) log.scans.push_back(scanOf(Pose2(1.0 + 0.2 * k, 2.0 + 0.03 * k, 0.1 * k), truth, rng));
  return log;
}

std::vector<MapSegment> room() {
  return {seg({0, 0}, {6, 0}), seg({6, 0}, {6, 4}), seg({6, 4}, {0, 4}), seg({0, 4}, {0, 0})};
}

TEST(ScanFit, AWallDrawnOffItsReturnsMovesOntoThemAndItsCornersFollow) {
  // The top wall drawn 7 cm too high (a SLAM map's bend, a shared line), its neighbours ending on it.
  const LaserLog log = roomLog(room());
  VectorizeResult plan;
  plan.map.segments = {seg({0, 0}, {6, 0}), seg({6, 0}, {6, 4.07}), seg({6, 4.07}, {0, 4.07}), seg({0, 4.07}, {0, 0})};
  const ScanFitStats st = fitToScans(plan, log, grid::BeamOptions{});
  const MapSegment& top = plan.map.segments[2];
  EXPECT_NEAR(top.a.y(), 4.0, 0.005);
  EXPECT_NEAR(top.b.y(), 4.0, 0.005);  // its direction kept
  EXPECT_NEAR(top.a.x(), 6.0, 1e-9);
  // The side walls end on the moved line: the corners stay closed.
  EXPECT_NEAR(plan.map.segments[1].b.y(), top.a.y(), 1e-9);
  EXPECT_NEAR(plan.map.segments[3].a.y(), top.b.y(), 1e-9);
  EXPECT_EQ(st.moved, 1u);  // the walls already on their returns stay
  EXPECT_NEAR(plan.map.segments[0].a.y(), 0.0, 1e-12);
  EXPECT_GE(st.junctions, 2u);
  EXPECT_GT(st.explained_after, st.explained_before);
}

TEST(ScanFit, FurnitureInFrontOfAWallDoesNotPullIt) {
  // A cabinet 12 cm in front of the bottom wall over a third of its length: the wall keeps the
  // densest band (its own face), where a mean of the returns would move it 4 cm into the room.
  std::vector<MapSegment> truth = room();
  truth.push_back(seg({2, 0.12}, {4, 0.12}));
  const LaserLog log = roomLog(truth);
  VectorizeResult plan;
  plan.map.segments = room();
  const ScanFitStats st = fitToScans(plan, log, grid::BeamOptions{});
  EXPECT_EQ(st.moved, 0u);
  EXPECT_NEAR(plan.map.segments[0].a.y(), 0.0, 1e-12);
}

TEST(ScanFit, GlassStaysAndDoorsFollowTheirWall) {
  const LaserLog log = roomLog(room());
  VectorizeResult plan;
  // The top wall in two pieces with a door between them, 6 cm high; the right wall drawn as glass
  // 5 cm out: glass is placed by its own evidence.
  plan.map.segments = {seg({0, 0}, {6, 0}), seg({6.05, 0}, {6.05, 4}, Material::Glass), seg({6, 4.06}, {3.5, 4.06}),
                       seg({2.5, 4.06}, {0, 4.06}), seg({0, 4.06}, {0, 0})};
  plan.extras.doors.push_back({{3.5, 4.06}, {2.5, 4.06}});
  fitToScans(plan, log, grid::BeamOptions{});
  EXPECT_EQ(plan.map.segments[1].a.x(), 6.05);
  EXPECT_NEAR(plan.map.segments[2].a.y(), 4.0, 0.005);
  EXPECT_NEAR(plan.map.segments[3].a.y(), 4.0, 0.005);
  EXPECT_NEAR(plan.extras.doors[0].a.y(), plan.map.segments[2].b.y(), 1e-9);
  EXPECT_NEAR(plan.extras.doors[0].b.y(), plan.map.segments[3].a.y(), 1e-9);
}

TEST(ScanFit, OffLeavesThePlanAndFewReturnsLeaveASegment) {
  const LaserLog log = roomLog(room());
  VectorizeResult plan;
  plan.map.segments = {seg({0, 4.07}, {6, 4.07})};
  ScanFitOptions off;
  off.enabled = false;
  fitToScans(plan, log, grid::BeamOptions{}, off);
  EXPECT_EQ(plan.map.segments[0].a.y(), 4.07);
  ScanFitOptions demanding;
  demanding.min_returns = 100000;
  const ScanFitStats st = fitToScans(plan, log, grid::BeamOptions{}, demanding);
  EXPECT_EQ(st.moved, 0u);
  EXPECT_EQ(plan.map.segments[0].a.y(), 4.07);
}

}  // namespace
}  // namespace glassmap::vector
