// No-return readings (grid/no_returns.hpp): with NoReturnMode::Angular a reading without an echo
// crosses cells only up to the first one that returned beams of its direction, so a wall that
// drops echoes is not seen through, while a pane met at a slant still is.
#include <gtest/gtest.h>

#include <cmath>

#include "glassmap/grid/no_returns.hpp"

namespace glassmap::grid {
namespace {

// A laser at (0, y) looking along +x over +-20 deg at a wall at x = 2 m; every tenth beam is a
// dropout (no return).
LaserLog droppingWallLog() {
  LaserLog log;
  for (int s = 0; s < 10; ++s) {
    LaserScan scan;
    scan.max_range = 10.0;
    scan.start_angle = deg2rad(-20.0);
    scan.angular_step = deg2rad(40.0 / 180.0);
    scan.laser_pose = Pose2(0.0, 0.1 * s, 0.0);
    for (int i = 0; i < 181; ++i)
      scan.ranges.push_back(i % 10 == s % 10 ? 10.0f : static_cast<float>(2.0 / std::cos(scan.beamAngle(i))));
    log.scans.push_back(scan);
  }
  return log;
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
  if (opt.deferNoReturns()) integrateNoReturns(log, opt, returnDirections(log, opt, hist), counts, hist);
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

TEST(NoReturns, APaneMetAtASlantIsCrossed) {
  // A pane along x = 2 returns only beams near its normal (within 3 deg); the others come back
  // with no echo. The laser sweeps +-40 deg from two places.
  LaserLog log;
  for (int s = 0; s < 20; ++s) {
    LaserScan scan;
    scan.max_range = 10.0;
    scan.start_angle = deg2rad(-40.0);
    scan.angular_step = deg2rad(1.0);
    scan.laser_pose = Pose2(0.0, 0.05 * s - 0.5, 0.0);
    for (int i = 0; i <= 80; ++i) {
      const double a = scan.beamAngle(i);
      scan.ranges.push_back(std::abs(rad2deg(a)) <= 3.0 ? static_cast<float>(2.0 / std::cos(a)) : 10.0f);
    }
    log.scans.push_back(scan);
  }
  const Passes p = run(log, NoReturnMode::Angular);
  // A pane cell near y = 0 was hit near the normal and missed at a slant.
  const CellIndex pane = p.g.cellAt(Vec2(2.01, -0.3));
  const std::int32_t id = p.hist.find(pane.x, pane.y);
  ASSERT_NE(id, AngleHistograms::kNone);
  int hits_near = 0, misses_slant = 0;
  for (int b = 0; b < 36; ++b) {
    const int d = std::min(b, 36 - b);
    if (d <= 1) hits_near += p.hist.hits(id)[b];
    if (d >= 3) misses_slant += p.hist.misses(id)[b];
  }
  EXPECT_GT(hits_near, 0);
  EXPECT_GT(misses_slant, 0);
}

}  // namespace
}  // namespace glassmap::grid
