// No-return readings (grid/no_returns.hpp): with NoReturnMode::Angular a reading without an echo
// crosses cells only up to the first one that returned beams of its direction, so a wall that
// drops echoes is not seen through, while a pane met at a slant still is.
#include <gtest/gtest.h>

#include <cmath>

#include "glassmap/grid/no_returns.hpp"
#include "grid_test_logs.hpp"

namespace glassmap::grid {
namespace {

// A laser at (0, y) looking along +x over +-20 deg at a wall at x = 2 m; every tenth beam is a
// dropout (no return).
LaserLog droppingWallLog() {
  return test::wallLog(10, [](int s, int i) { return i % 10 == s % 10; });
}

struct Passes {
  GridGeometry g;
  HitMissGrid counts;
  AngleHistograms hist;
};

Passes run(const LaserLog& log, NoReturnMode mode, double cap = 8.0) {
  BeamOptions opt;
  opt.range_cap = cap;
  opt.no_return = mode;
  opt.miss_margin = 0.0;
  const GridGeometry g = geometryForLog(log, 0.05, opt);
  HitMissGrid counts(g);
  integrateCounts(log, opt, counts);
  AngleHistograms hist(counts, 36);
  integrateNoReturns(log, opt, counts, hist);
  integrateAngles(log, opt, hist);
  return {g, std::move(counts), std::move(hist)};
}

TEST(NoReturns, AWallThatDropsEchoesIsNotSeenThrough) {
  const LaserLog log = droppingWallLog();
  const Passes open = run(log, NoReturnMode::Open);
  const Passes angular = run(log, NoReturnMode::Angular);
  // Open: the dropouts cross the wall and clear the space behind it.
  const CellIndex behind = open.g.cellAt(Vec2(4.0, 0.45));
  EXPECT_GT(open.counts.get(behind.x, behind.y).misses, 0);
  // Angular: the grid ends with what returned; the wall's cells get no miss from its dropouts.
  EXPECT_LT(angular.g.width, open.g.width);
  const CellIndex wall = angular.g.cellAt(Vec2(2.01, 0.45));
  const std::int32_t id = angular.hist.find(wall.x, wall.y);
  ASSERT_NE(id, AngleHistograms::kNone);
  int misses = 0;
  for (int b = 0; b < 36; ++b) misses += angular.hist.misses(id)[b];
  EXPECT_EQ(misses, 0);
  // Free space before the wall is still cleared by them.
  const CellIndex before = angular.g.cellAt(Vec2(1.0, 0.45));
  EXPECT_GT(angular.counts.get(before.x, before.y).misses, open.counts.get(before.x, before.y).misses / 2);
}

// A pane along x = 2 returns beams within 3 deg of its normal, and others with probability
// `floor` (a sensor's floor of direct returns at any angle); the rest come back with no echo. The
// laser sweeps +-40 deg from 20 places.
LaserLog paneLog(double floor) {
  LaserLog log;
  std::uint64_t state = 7;
  auto uniform = [&state] {  // a small LCG: deterministic everywhere
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) * 0x1.0p-53;
  };
  for (int s = 0; s < 20; ++s) {
    LaserScan scan;
    scan.max_range = 10.0;
    scan.start_angle = deg2rad(-40.0);
    scan.angular_step = deg2rad(1.0);
    scan.laser_pose = Pose2(0.0, 0.05 * s - 0.5, 0.0);
    for (int i = 0; i <= 80; ++i) {
      const double a = scan.beamAngle(i);
      const bool echo = std::abs(rad2deg(a)) <= 3.0 || uniform() < floor;
      scan.ranges.push_back(echo ? static_cast<float>(2.0 / std::cos(a)) : 10.0f);
    }
    log.scans.push_back(scan);
  }
  return log;
}

class PaneMetAtASlant : public ::testing::TestWithParam<double> {};

// Hits within a bin of the normal and misses three bins or more off it, of the pane cell at y.
std::pair<int, int> nearHitsAndSlantMisses(const Passes& p, double y) {
  const CellIndex pane = p.g.cellAt(Vec2(2.01, y));
  const std::int32_t id = p.hist.find(pane.x, pane.y);
  if (id == AngleHistograms::kNone) return {-1, -1};
  int hits_near = 0, misses_slant = 0;
  for (int b = 0; b < 36; ++b) {
    const int d = std::min(b, 36 - b);
    if (d <= 1) hits_near += p.hist.hits(id)[b];
    if (d >= 3) misses_slant += p.hist.misses(id)[b];
  }
  return {hits_near, misses_slant};
}

TEST_P(PaneMetAtASlant, IsCrossedEvenWithAFloorOfReturns) {
  const LaserLog log = paneLog(GetParam());
  const Passes angular = run(log, NoReturnMode::Angular), open = run(log, NoReturnMode::Open);
  for (const double y : {-0.3, 0.0, 0.2}) {
    const auto [hits, slant] = nearHitsAndSlantMisses(angular, y);
    const auto [hits_open, slant_open] = nearHitsAndSlantMisses(open, y);
    EXPECT_GT(hits, 0) << y;
    EXPECT_EQ(hits, hits_open) << y;
    // The pane stops only the no-returns of the directions it mostly returns (near its normal).
    EXPECT_GT(slant, 0) << y;
    EXPECT_GE(slant, slant_open * 3 / 4) << "floor " << GetParam() << ", y " << y;
  }
}

INSTANTIATE_TEST_SUITE_P(Floors, PaneMetAtASlant, ::testing::Values(0.0, 0.05, 0.15));

}  // namespace
}  // namespace glassmap::grid
