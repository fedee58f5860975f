// Tests of the grid module: geometry, exact traversal, counts, occupancy, angle bins.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <utility>

#include <tbb/global_control.h>

#include "glassmap/core/error.hpp"
#include "glassmap/grid/angle_histograms.hpp"
#include "glassmap/grid/distance_transform.hpp"
#include "glassmap/grid/scan_integration.hpp"
#include "glassmap/grid/traversal.hpp"
#include "grid_test_logs.hpp"

namespace glassmap::grid {
namespace {

GridGeometry smallGrid() {
  GridGeometry g;
  g.resolution = 0.1;
  g.origin = Vec2(-1.0, -2.0);
  g.width = 40;
  g.height = 30;
  return g;
}

// Brute force: every cell whose closed box the segment meets with positive length.
std::set<std::pair<int, int>> bruteForceCells(const GridGeometry& g, const Vec2& a, const Vec2& b) {
  std::set<std::pair<int, int>> out;
  for (int y = 0; y < g.height; ++y) {
    for (int x = 0; x < g.width; ++x) {
      GridGeometry cell = g;
      cell.origin = g.origin + Vec2(x * g.resolution, y * g.resolution);
      cell.width = cell.height = 1;
      double t0 = 0, t1 = 1;
      if (clipToGrid(cell, a, b, t0, t1) && (t1 - t0) * (b - a).norm() > 1e-9) out.insert({x, y});
    }
  }
  return out;
}

TEST(GridGeometry, IndexAndCells) {
  const GridGeometry g = smallGrid();
  EXPECT_EQ(g.cells(), 1200U);
  const CellIndex c = g.cellAt(Vec2(-0.95, -1.95));
  EXPECT_EQ(c, (CellIndex{0, 0}));
  EXPECT_EQ(g.cellAt(Vec2(0.05, 0.05)), (CellIndex{10, 20}));
  EXPECT_EQ(g.cellOf(g.index(7, 9)), (CellIndex{7, 9}));
  EXPECT_NEAR(g.center(10, 20).x(), 0.05, 1e-12);
  const GridGeometry cov = coveringGeometry(Vec2(0.02, 0.03), Vec2(1.0, 2.0), 0.05, 0.1);
  EXPECT_LE(cov.origin.x(), -0.08 + 1e-9);
  EXPECT_GE(cov.maxCorner().x(), 1.1 - 1e-9);
  EXPECT_GE(cov.maxCorner().y(), 2.1 - 1e-9);
}

TEST(Traversal, EqualsBruteForceOnRandomRays) {
  const GridGeometry g = smallGrid();
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> ux(-1.5, 3.5), uy(-2.5, 1.5);
  for (int trial = 0; trial < 400; ++trial) {
    const Vec2 a(ux(rng), uy(rng)), b(ux(rng), uy(rng));
    const auto cells = touchedCells(g, a, b);
    std::set<std::pair<int, int>> got;
    for (const auto& c : cells) got.insert({c.x, c.y});
    EXPECT_EQ(got.size(), cells.size()) << "a cell visited twice";
    EXPECT_EQ(got, bruteForceCells(g, a, b)) << "trial " << trial;
    // Consecutive cells are 4-neighbours and the walk ends in b's cell when b is inside.
    for (std::size_t i = 1; i < cells.size(); ++i) {
      EXPECT_EQ(std::abs(cells[i].x - cells[i - 1].x) + std::abs(cells[i].y - cells[i - 1].y), 1);
    }
    if (g.contains(g.cellAt(b)) && !cells.empty()) {
      EXPECT_EQ(cells.back(), g.cellAt(b));
    }
    if (g.contains(g.cellAt(a)) && !cells.empty()) {
      EXPECT_EQ(cells.front(), g.cellAt(a));
    }
  }
}

// lastCell names the cell the walk ends in without walking, on random segments and on segments
// whose end lies on cell borders and grid corners (where rounding would decide it).
TEST(Traversal, LastCellIsTheWalksLastCell) {
  const GridGeometry g = smallGrid();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ux(-1.5, 3.5), uy(-2.5, 1.5);
  std::uniform_int_distribution<int> border(0, 30);
  int compared = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    Vec2 a(ux(rng), uy(rng)), b(ux(rng), uy(rng));
    if (trial % 2) b = g.origin + g.resolution * Vec2(border(rng), border(rng));  // on a border or corner
    CellIndex last{-1, -1};
    bool seen = false;
    traverse(g, a, b, [&](int x, int y, double, bool is_last) {
      if (is_last) last = {x, y}, seen = true;
    });
    CellIndex c;
    ASSERT_EQ(lastCell(g, a, b, c), seen) << "trial " << trial;
    if (seen) {
      EXPECT_EQ(c, last) << "trial " << trial;
      ++compared;
    }
  }
  EXPECT_GT(compared, 1000);
}

TEST(Traversal, AWalkFromAParameterIsTheFullWalksRest) {
  const GridGeometry g = smallGrid();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> ux(-1.5, 3.5), uy(-2.5, 1.5), u01(0.0, 1.0);
  int compared = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const Vec2 a(ux(rng), uy(rng)), b(ux(rng), uy(rng));
    std::vector<std::pair<CellIndex, double>> full;
    traverse(g, a, b, [&](int x, int y, double t, bool) { full.push_back({{x, y}, t}); });
    if (full.size() < 2) continue;
    // From inside the k-th cell: the k-th cell on, entered at the start parameter, `last` kept.
    const std::size_t k = std::uniform_int_distribution<std::size_t>(0, full.size() - 1)(rng);
    double t0 = 0.0, t1 = 1.0;  // the walk ends where the segment leaves the grid
    ASSERT_TRUE(clipToGrid(g, a, b, t0, t1));
    const double t_next = k + 1 < full.size() ? full[k + 1].second : t1;
    const double t_from = full[k].second + (0.1 + 0.8 * u01(rng)) * (t_next - full[k].second);
    std::vector<CellIndex> rest;
    bool last_seen = false;
    double first_t = -1.0;
    traverse(
        g, a, b,
        [&](int x, int y, double t, bool last) {
          if (rest.empty()) first_t = t;
          rest.push_back({x, y});
          last_seen = last;
        },
        t_from);
    ASSERT_EQ(rest.size(), full.size() - k) << "trial " << trial;
    for (std::size_t i = 0; i < rest.size(); ++i) EXPECT_EQ(rest[i], full[k + i].first) << "trial " << trial;
    EXPECT_DOUBLE_EQ(first_t, t_from);
    EXPECT_TRUE(last_seen);
    ++compared;
  }
  EXPECT_GT(compared, 1500);
  // Past the end: nothing.
  EXPECT_EQ(traverse(
                g, Vec2(0.01, 0.01), Vec2(1.0, 0.5), [](int, int, double, bool) {}, 1.5),
            0U);
}

TEST(Traversal, AxisAlignedAndSingleCell) {
  const GridGeometry g = smallGrid();
  const auto row = touchedCells(g, Vec2(-0.95, -1.95), Vec2(0.05, -1.95));
  ASSERT_EQ(row.size(), 11U);
  for (int i = 0; i < 11; ++i) EXPECT_EQ(row[i], (CellIndex{i, 0}));
  const auto one = touchedCells(g, Vec2(0.01, 0.01), Vec2(0.02, 0.03));
  ASSERT_EQ(one.size(), 1U);
  EXPECT_TRUE(touchedCells(g, Vec2(-5, -5), Vec2(-4, -5)).empty());
}

TEST(Traversal, EnterParameterIsMonotoneAndOnCellBorders) {
  const GridGeometry g = smallGrid();
  const Vec2 a(-0.93, -1.91), b(2.71, 0.77);
  double prev = -1.0;
  traverse(g, a, b, [&](int x, int y, double t, bool) {
    EXPECT_GE(t, prev);
    prev = t;
    const Vec2 p = a + t * (b - a);  // on the cell's border (or the start)
    const Vec2 lo = g.origin + Vec2(x * g.resolution, y * g.resolution);
    EXPECT_GE(p.x(), lo.x() - 1e-9);
    EXPECT_LE(p.x(), lo.x() + g.resolution + 1e-9);
    EXPECT_GE(p.y(), lo.y() - 1e-9);
    EXPECT_LE(p.y(), lo.y() + g.resolution + 1e-9);
  });
}

TEST(Occupancy, HitsOccupyMissesFree) {
  OccupancyModel m;
  EXPECT_GT(m.logOdds({3, 0}), 0.0);
  EXPECT_LT(m.logOdds({0, 3}), 0.0);
  EXPECT_TRUE(m.occupied({5, 2}));
  EXPECT_FALSE(m.occupied({1, 10}));
  EXPECT_NEAR(m.probability({100, 0}), 0.97, 1e-3);  // clamped
  EXPECT_NEAR(m.probability({0, 100}), 0.12, 1e-3);
}

// Five scans at the wall; beam 90 of each is a max-range reading (clears, no hit).
LaserLog wallLog() {
  return test::wallLog(5, [](int, int i) { return i == 90; });
}

TEST(ScanIntegration, WallIsOccupiedAndFreeSpaceFree) {
  const LaserLog log = wallLog();
  BeamOptions opt;
  opt.range_cap = 8.0;
  opt.no_return = NoReturnMode::Open;  // the classic reading: a no-return clears up to the cap
  const GridGeometry g = geometryForLog(log, 0.05, opt);
  HitMissGrid grid(g);
  const IntegrationStats st = integrateCounts(log, opt, grid);
  EXPECT_EQ(st.beams, 5U * 181U);
  EXPECT_EQ(st.hit_beams, 5U * 180U);
  OccupancyModel m;
  const CellIndex wall = g.cellAt(Vec2(2.01, 0.2));
  EXPECT_TRUE(m.occupied(grid.get(wall.x, wall.y)));
  const CellIndex free_cell = g.cellAt(Vec2(1.0, 0.2));
  EXPECT_LT(m.logOdds(grid.get(free_cell.x, free_cell.y)), 0.0);
  // The max-range beam (straight ahead) cleared cells behind the wall up to the cap, no hit there.
  const CellIndex behind = g.cellAt(Vec2(7.5, 0.0));
  EXPECT_EQ(grid.get(behind.x, behind.y).hits, 0);
  EXPECT_GT(grid.get(behind.x, behind.y).misses, 0);
  // Memory follows what was seen: exactly the tiles holding an observed cell are allocated, fewer
  // than the bounding box holds.
  std::set<std::pair<int, int>> seen_tiles;
  std::size_t observed = 0;
  for (int y = 0; y < g.height; ++y) {
    for (int x = 0; x < g.width; ++x) {
      const CellCounts c = grid.get(x, y);
      if (c.hits == 0 && c.misses == 0) continue;
      ++observed;
      seen_tiles.emplace(x >> HitMissGrid::kTileBits, y >> HitMissGrid::kTileBits);
    }
  }
  EXPECT_GT(observed, 100U);
  EXPECT_EQ(grid.observedCells(), observed);
  EXPECT_EQ(grid.allocatedTiles(), seen_tiles.size());
  const int box_tiles_x = (g.width + HitMissGrid::kTileSize - 1) / HitMissGrid::kTileSize;
  const int box_tiles_y = (g.height + HitMissGrid::kTileSize - 1) / HitMissGrid::kTileSize;
  EXPECT_LT(grid.allocatedTiles(), static_cast<std::size_t>(box_tiles_x * box_tiles_y) / 2);
}

TEST(AngleHistograms, BinsWrapAtHalfTurn) {
  EXPECT_EQ(angleBin(0.0, 36), 0);
  EXPECT_EQ(angleBin(kPi, 36), 0);
  EXPECT_EQ(angleBin(deg2rad(179.0), 36), 0);
  EXPECT_EQ(angleBin(deg2rad(2.4), 36), 0);
  EXPECT_EQ(angleBin(deg2rad(2.6), 36), 1);
  EXPECT_EQ(angleBin(deg2rad(-90.0), 36), 18);
  EXPECT_EQ(angleBin(deg2rad(275.0), 36), 19);
  EXPECT_EQ(angleBin(deg2rad(45.0), 36), 9);
}

TEST(AngleHistograms, HitsAndMissesLandInTheBeamBin) {
  const LaserLog log = wallLog();
  BeamOptions opt;
  opt.range_cap = 8.0;
  const GridGeometry g = geometryForLog(log, 0.05, opt);
  HitMissGrid grid(g);
  integrateCounts(log, opt, grid);
  AngleHistograms hist(grid, 36);
  ASSERT_GT(hist.size(), 0U);
  integrateAngles(log, opt, hist);
  // The wall cell straight ahead of the first pose is hit by beams within atan(0.4 / 2) = 11.3 deg
  // of 0 deg (poses y = 0 .. 0.4 m): bins 34, 35, 0, 1, 2 only, most of them in bin 0.
  const CellIndex c = g.cellAt(Vec2(2.01, 0.0));
  const std::int32_t id = hist.find(c.x, c.y);
  ASSERT_NE(id, AngleHistograms::kNone);
  int near = 0, total = 0;
  for (int b = 0; b < 36; ++b) {
    total += hist.hits(id)[b];
    if (b <= 2 || b >= 34) near += hist.hits(id)[b];
  }
  EXPECT_GT(hist.hits(id)[0], 0);
  EXPECT_EQ(near, total);
  EXPECT_GE(hist.hits(id)[0], hist.hits(id)[2]);
  // Totals of a candidate equal the counts of pass 1.
  for (std::size_t i = 0; i < hist.size(); ++i) {
    const auto cell = g.cellOf(hist.cell(static_cast<std::int32_t>(i)));
    int h = 0, mi = 0;
    for (int b = 0; b < 36; ++b) {
      h += hist.hits(static_cast<std::int32_t>(i))[b];
      mi += hist.misses(static_cast<std::int32_t>(i))[b];
    }
    EXPECT_EQ(h, grid.get(cell.x, cell.y).hits);
    EXPECT_EQ(mi, grid.get(cell.x, cell.y).misses);
  }
  // A free cell is no candidate.
  const CellIndex f = g.cellAt(Vec2(1.0, 0.2));
  EXPECT_EQ(hist.find(f.x, f.y), AngleHistograms::kNone);
}

}  // namespace
}  // namespace glassmap::grid

namespace glassmap::grid {
namespace {

// Parts merged: saturating sums, the same whatever the split.
TEST(ParallelPasses, MergeSaturatesAndEqualsOneGo) {
  const GridGeometry g = coveringGeometry(Vec2(0, 0), Vec2(3, 3), 0.05, 0.0);
  HitMissGrid a(g), b(g), whole(g);
  for (int i = 0; i < 40000; ++i) {
    a.addHit(3, 4);
    whole.addHit(3, 4);
  }
  for (int i = 0; i < 40000; ++i) {
    b.addHit(3, 4);
    whole.addHit(3, 4);
  }
  b.addMiss(50, 50);
  whole.addMiss(50, 50);
  a.merge(b);
  EXPECT_EQ(a.get(3, 4).hits, 0xFFFF);
  EXPECT_EQ(whole.get(3, 4).hits, 0xFFFF);
  EXPECT_EQ(a.get(50, 50).misses, 1);
  EXPECT_EQ(a.observedCells(), whole.observedCells());
  HitMissGrid other(coveringGeometry(Vec2(0, 0), Vec2(9, 9), 0.05, 0.0));
  EXPECT_THROW(a.merge(other), Error);

  AngleHistograms hist(a, 36);
  ASSERT_EQ(hist.size(), 1U);
  std::vector<std::uint16_t> part = hist.emptyCounts();
  hist.addHit(part, 0, 5);
  hist.addMiss(part, 0, 7);
  hist.merge(part);
  hist.merge(part);
  EXPECT_EQ(hist.hits(0)[5], 2);
  EXPECT_EQ(hist.misses(0)[7], 2);
  EXPECT_EQ(hist.hits(0)[7], 0);
}

// The passes give the same counts on one thread and on several.
TEST(ParallelPasses, CountsAndHistogramsDoNotDependOnTheThreadCount) {
  LaserLog log;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> r(0.5, 6.0);
  for (int s = 0; s < 300; ++s) {
    LaserScan scan;
    scan.max_range = 8.0;
    scan.start_angle = deg2rad(-90.0);
    scan.angular_step = deg2rad(1.0);
    scan.laser_pose = Pose2(0.01 * s, 0.02 * (s % 7), 0.01 * s);
    for (int i = 0; i < 181; ++i) scan.ranges.push_back(static_cast<float>(r(rng)));
    log.scans.push_back(scan);
  }
  BeamOptions opt;
  const GridGeometry g = geometryForLog(log, 0.05, opt);
  auto run = [&](int threads, std::vector<std::uint16_t>& hist_out) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    HitMissGrid grid(g);
    const IntegrationStats st = integrateCounts(log, opt, grid);
    AngleHistograms hist(grid, 36);
    integrateAngles(log, opt, hist);
    hist_out.clear();
    for (std::size_t i = 0; i < hist.size(); ++i)
      hist_out.insert(hist_out.end(), hist.hits(static_cast<std::int32_t>(i)),
                      hist.hits(static_cast<std::int32_t>(i)) + 72);
    std::vector<std::uint32_t> cells;
    for (int y = 0; y < g.height; ++y)
      for (int x = 0; x < g.width; ++x) {
        const CellCounts c = grid.get(x, y);
        cells.push_back((std::uint32_t{c.hits} << 16) | c.misses);
      }
    EXPECT_EQ(st.beams, 300U * 181U);
    return cells;
  };
  std::vector<std::uint16_t> h1, h4;
  const auto c1 = run(1, h1);
  const auto c4 = run(4, h4);
  EXPECT_EQ(c1, c4);
  EXPECT_EQ(h1, h4);
  EXPECT_FALSE(h1.empty());
}

// Each filter hands out exactly the beams of its kind, field for field the beams of BeamFilter::All.
TEST(ScanIntegration, BeamFiltersHandOutTheBeamsOfTheirKindUnchanged) {
  LaserScan scan;
  scan.max_range = 8.0;
  scan.start_angle = deg2rad(-90.0);
  scan.angular_step = deg2rad(0.7);
  scan.laser_pose = Pose2(1.3, -0.4, 0.9);
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  // Returns, one in the dead zone, ones beyond the cap, max-range and non-finite readings.
  for (float r : {2.5f, 0.01f, 7.0f, 8.0f, 9.5f, inf, nan, 4.0f, 3.25f, 8.0f}) scan.ranges.push_back(r);
  BeamOptions opt;
  opt.range_cap = 5.0;
  opt.no_return_range = 6.0;
  auto collect = [&](BeamFilter f) {
    std::vector<Beam> out;
    forEachBeam(
        scan, opt, [&](const Beam& b) { out.push_back(b); }, f);
    return out;
  };
  const std::vector<Beam> all = collect(BeamFilter::All);
  auto same = [](const std::vector<Beam>& got, const std::vector<Beam>& want) {
    ASSERT_EQ(got.size(), want.size());
    for (std::size_t i = 0; i < got.size(); ++i) {
      EXPECT_EQ(got[i].from, want[i].from);
      EXPECT_EQ(got[i].to, want[i].to);  // bit for bit: the same trigonometry
      EXPECT_EQ(got[i].angle, want[i].angle);
      EXPECT_EQ(got[i].range, want[i].range);
      EXPECT_EQ(got[i].hit, want[i].hit);
      EXPECT_EQ(got[i].no_return, want[i].no_return);
    }
  };
  std::vector<Beam> returned, no_return, hit;
  for (const Beam& b : all) {
    (b.no_return ? no_return : returned).push_back(b);
    if (b.hit) hit.push_back(b);
  }
  EXPECT_EQ(all.size(), 9U);  // the dead-zone reading is dropped
  EXPECT_EQ(hit.size(), 3U);  // 7 m returned beyond the 5 m cap: returned, no hit
  EXPECT_EQ(no_return.size(), 5U);
  same(collect(BeamFilter::Returned), returned);
  same(collect(BeamFilter::NoReturn), no_return);
  same(collect(BeamFilter::Hit), hit);
  opt.clear_no_return = false;
  EXPECT_TRUE(collect(BeamFilter::NoReturn).empty());
  EXPECT_EQ(passBeams(opt), BeamFilter::All);
  opt.clear_no_return = true;
  EXPECT_EQ(passBeams(opt), BeamFilter::Returned);
}

// The walk cursors count and find exactly what the grid's own calls do, across tile borders.
TEST(ScanIntegration, BeamDirectionsFromTheLayoutTableAreTheBeamAngles) {
  // Six layouts in turn (more than a thread keeps), each scan at its own heading: every beam's end
  // lies along its angle within rounding, and a layout's table is the same one when it comes back.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> heading(-kPi, kPi), range(0.2, 25.0);
  for (int round = 0; round < 3; ++round)
    for (int layout = 0; layout < 6; ++layout) {
      LaserScan scan;
      scan.start_angle = -kPi / 2 - 0.1 * layout;
      scan.angular_step = kPi / (90.0 + 10.0 * layout);
      scan.max_range = 30.0;
      scan.ranges.resize(static_cast<std::size_t>(91 + 10 * layout));
      for (float& r : scan.ranges) r = static_cast<float>(range(rng));
      scan.laser_pose = Pose2(Vec2(3.0 * layout, -1.5), heading(rng));
      const auto table = beamDirections(scan);
      ASSERT_EQ(table->cos.size(), scan.ranges.size());
      EXPECT_EQ(beamDirections(scan), table);  // kept, not made again
      std::size_t beams = 0;
      forEachBeam(scan, BeamOptions{}, [&](const Beam& beam) {
        const Vec2 expected = beam.from + beam.range * Vec2(std::cos(beam.angle), std::sin(beam.angle));
        EXPECT_NEAR(beam.to.x(), expected.x(), 1e-12 * (1.0 + beam.range));
        EXPECT_NEAR(beam.to.y(), expected.y(), 1e-12 * (1.0 + beam.range));
        ++beams;
      });
      EXPECT_EQ(beams, scan.ranges.size());
    }
}

TEST(ScanIntegration, CursorsEqualTheGridsOwnLookups) {
  GridGeometry g = smallGrid();
  g.width = 100;
  g.height = 70;
  HitMissGrid direct(g), walked(g);
  HitMissGrid::Cursor cursor(walked);
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> ux(0, g.width - 1), uy(0, g.height - 1), coin(0, 1);
  for (int k = 0; k < 20000; ++k) {
    const int x = ux(rng), y = uy(rng);
    if (coin(rng)) {
      direct.addHit(x, y);
      cursor.addHit(x, y);
    } else {
      direct.addMiss(x, y);
      cursor.addMiss(x, y);
    }
  }
  EXPECT_EQ(direct.allocatedTiles(), walked.allocatedTiles());
  AngleHistograms hist(direct, 36, 2);
  AngleHistograms::Cursor find(hist);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const CellCounts a = direct.get(x, y), b = walked.get(x, y);
      EXPECT_EQ(a.hits, b.hits);
      EXPECT_EQ(a.misses, b.misses);
    }
  // Rows and columns both ways, so the cursor steps across tiles in every direction.
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) EXPECT_EQ(find.find(x, y), hist.find(x, y));
  for (int x = g.width - 1; x >= 0; --x)
    for (int y = g.height - 1; y >= 0; --y) EXPECT_EQ(find.find(x, y), hist.find(x, y));
  EXPECT_GT(hist.size(), 0U);
}

}  // namespace
}  // namespace glassmap::grid

namespace glassmap::grid {
namespace {

// The exact Euclidean distance transform against brute force on random rasters (one with no source).
TEST(DistanceTransform, MatchesBruteForce) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    const int w = 5 + trial % 7, h = 3 + trial % 5;
    std::vector<std::uint8_t> src(static_cast<std::size_t>(w) * h, 0);
    if (trial > 0)
      for (auto& v : src) v = rng() % 9 == 0;
    const std::vector<float> d = distanceTransform(w, h, src);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        double best = std::numeric_limits<double>::infinity();
        for (int yy = 0; yy < h; ++yy)
          for (int xx = 0; xx < w; ++xx)
            if (src[static_cast<std::size_t>(yy) * w + xx]) best = std::min(best, std::hypot(xx - x, yy - y));
        const float got = d[static_cast<std::size_t>(y) * w + x];
        if (std::isinf(best))
          EXPECT_TRUE(std::isinf(got));
        else
          EXPECT_NEAR(got, best, 1e-4) << "trial " << trial << " cell " << x << "," << y;
      }
  }
}

}  // namespace
}  // namespace glassmap::grid
