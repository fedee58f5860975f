// Tests of the glass module: labels, lobe, both classifiers on synthetic scans, rendering.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <random>

#include "glassmap/core/error.hpp"
#include "glassmap/geometry/ray_caster.hpp"
#include "glassmap/glass/mapping.hpp"
#include "glassmap/glass/scan_coherence.hpp"
#include "glassmap/glass/sparse_panes.hpp"

namespace glassmap::glass {
namespace {

// A 10 m x 6 m room split by a wall at x = 5 with a glass pane in it (y = 1.5 .. 4.5, normal
// along x: GLS_0), beams synthesised by ray casting with the simulator's glass physics reduced to
// its core: a direct return within ~3 deg of the normal, a pass-through otherwise.
VectorMap scene() {
  VectorMap m;
  auto add = [&](Vec2 a, Vec2 b, Material mat) { m.add(a, b, mat); };
  add({0, 0}, {10, 0}, Material::Wall);
  add({10, 0}, {10, 6}, Material::Wall);
  add({10, 6}, {0, 6}, Material::Wall);
  add({0, 6}, {0, 0}, Material::Wall);
  add({5, 0}, {5, 1.5}, Material::Wall);
  add({5, 4.5}, {5, 6}, Material::Wall);
  add({5, 1.5}, {5, 4.5}, Material::Glass);
  return m;
}

LaserLog synthLog(const VectorMap& map, std::uint64_t seed) {
  RayCaster caster(map);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.01);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  LaserLog log;
  // Drive up and down the left room facing the pane, then along the right room.
  std::vector<Pose2> poses;
  for (double y = 1.0; y <= 5.0; y += 0.05) poses.emplace_back(2.5, y, 0.0);
  for (double x = 6.0; x <= 9.0; x += 0.1) poses.emplace_back(x, 3.0, kPi / 2);
  for (double x = 1.0; x <= 4.0; x += 0.1) poses.emplace_back(x, 1.0, kPi / 4);
  for (const Pose2& pose : poses) {
    LaserScan scan;
    scan.max_range = 20.0;
    scan.start_angle = deg2rad(-135.0);
    scan.angular_step = deg2rad(0.5);
    scan.laser_pose = pose;
    for (int i = 0; i < 541; ++i) {
      const double a = pose.theta + scan.beamAngle(i);
      RayHit hit = caster.cast(pose.t, a, scan.max_range);
      double travelled = 0.0;
      Vec2 origin = pose.t;
      while (hit.hit() && hit.material == Material::Glass) {
        const double p_direct = 0.9 * std::exp(-std::pow(rad2deg(hit.incidence), 2) / (2 * 9.0));
        if (u(rng) < p_direct) break;  // direct return from the pane
        travelled += hit.range;        // pass through
        origin = origin + hit.range * Vec2(std::cos(a), std::sin(a));
        const std::int32_t skip = hit.segment;
        hit = caster.cast(origin, a, scan.max_range - travelled, skip);
      }
      scan.ranges.push_back(hit.hit() ? static_cast<float>(travelled + hit.range + noise(rng))
                                      : static_cast<float>(scan.max_range));
    }
    log.scans.push_back(std::move(scan));
  }
  return log;
}

struct Tally {
  int glass_right = 0, glass_other = 0, occ = 0, total = 0;
};

Tally tallyLine(const CellEvidence& e, Vec2 a, Vec2 b, int want_bin) {
  Tally t;
  const int n = 60;
  grid::CellIndex last{-1, -1};
  for (int i = 0; i <= n; ++i) {
    const grid::CellIndex c = e.geometry.cellAt(a + (b - a) * (static_cast<double>(i) / n) + Vec2(1e-4, 1e-4));
    if (c == last) continue;
    last = c;
    // The cell or a 4-neighbour (discretisation puts the pane on a cell border).
    bool right = false, other = false, occ = false;
    for (auto [dx, dy] : {std::pair{0, 0}, {-1, 0}, {1, 0}, {0, -1}, {0, 1}}) {
      const int l = e.label[e.geometry.index(c.x + dx, c.y + dy)];
      if (isGlass(l) && (glassBin(l) == want_bin))
        right = true;
      else if (isGlass(l))
        other = true;
      else if (l == kOccupied)
        occ = true;
    }
    ++t.total;
    t.glass_right += right;
    t.glass_other += (!right && other);
    t.occ += occ;
  }
  return t;
}

TEST(Labels, CodesRoundTrip) {
  EXPECT_EQ(labelToCode(kUnknown), 0);
  EXPECT_EQ(labelToCode(kEmpty), 1);
  EXPECT_EQ(labelToCode(kOccupied), 2);
  EXPECT_EQ(labelToCode(glassLabel(7)), 17);
  for (int l : {int(kUnknown), kEmpty, kOccupied, glassLabel(0), glassLabel(35)}) {
    EXPECT_EQ(codeToLabel(labelToCode(l)), l);
  }
  EXPECT_EQ(numLabels(), 38);
}

TEST(DirectLobe, PeaksAtNormalAndFallsOff) {
  DirectOptions o;
  const auto lobe = directLobe(36, o);
  ASSERT_EQ(lobe.size(), 19U);
  // sigma 2 deg, peak 0.9, averaged over 5 deg bins: 0.712, 0.095, 8e-5, then the floor.
  EXPECT_NEAR(lobe[0], 0.712, 0.002);
  EXPECT_NEAR(lobe[1], 0.095, 0.002);
  EXPECT_LT(lobe[2], 1e-3 + 1e-4);
  EXPECT_DOUBLE_EQ(lobe[10], o.lobe_floor);
}

TEST(PaneLanding, ACellOfAPaneSeesTheShareOfItsReturnsThatLandInIt) {
  const double res = 0.05;
  const PaneLanding exact(36, res, 0.0, 0.1);
  // An axis-aligned pane lies in one row of cells: a beam along its normal enters one pane cell
  // and its reading falls in it.
  EXPECT_GT(exact.hit(0, 0), 0.95);
  EXPECT_LT(exact.miss(0, 0), 0.01);
  // A pane at 45 deg runs through two cells per row: a beam along its normal enters two of them
  // and leaves its one hit in one.
  EXPECT_NEAR(exact.hit(9, 0), 0.5, 0.05);
  // The more oblique the beam, the more pane cells it passes per return.
  EXPECT_LT(exact.hit(0, 12), 0.8 * exact.hit(0, 2));
  // A pane and its mirror image across the x axis meet the grid alike.
  for (int d = 0; d <= 18; ++d) EXPECT_DOUBLE_EQ(exact.hit(5, d), exact.hit(31, d));
  // Range noise moves readings off the pane's cells.
  const PaneLanding noisy(36, res, res, 0.15);
  EXPECT_LT(noisy.hit(0, 0), 0.8 * exact.hit(0, 0));
  // The same table every time (a fixed seed).
  const PaneLanding again(36, res, 0.0, 0.1);
  for (int k = 0; k < 36; ++k)
    for (int d = 0; d <= 18; ++d) EXPECT_EQ(exact.hit(k, d), again.hit(k, d));
  // What returns every beam shows every beam as a hit (a wall stays a wall); what returns none, none.
  EXPECT_NEAR(exact.cellRate(9, 0, 1.0), 1.0, 1e-9);
  EXPECT_EQ(exact.cellRate(9, 0, 0.0), 0.0);
  // A pane at 45 deg that returns 30% of the beams along its normal shows about half that per cell.
  EXPECT_NEAR(exact.cellRate(9, 0, 0.3), 0.3 * 0.5 / (0.3 * 0.5 + 0.7), 0.02);
  EXPECT_THROW(PaneLanding(36, 0.0, 0.0, 0.1), Error);
  // 1 deg bins (fewer beams per entry, as many in all): the same shape.
  const PaneLanding fine(180, res, 0.0, 0.1);
  EXPECT_GT(fine.hit(0, 0), 0.95);
  EXPECT_NEAR(fine.hit(45, 0), 0.5, 0.08);
}

class Classifiers : public ::testing::TestWithParam<Method> {};

TEST_P(Classifiers, PaneIsGlassAtItsAngleAndWallsAreOccupied) {
  const VectorMap map = scene();
  const LaserLog log = synthLog(map, 7);
  MappingOptions o;
  o.method = GetParam();
  const MappingResult r = mapLog(log, o);
  const CellEvidence& e = r.evidence;
  ASSERT_EQ(e.label.size(), e.geometry.cells());
  EXPECT_EQ(e.num_labels, 38);
  EXPECT_GT(r.stats.glass_cells, 0U);
  // The pane, away from its ends: glass in bin 0 along most of it (the heuristic, the paper's
  // weakest method, along half of it: measured 28 of 49 cells, direct 49 of 49).
  const Tally pane = tallyLine(e, {5.0, 1.8}, {5.0, 4.2}, 0);
  const double want = GetParam() == Method::Direct ? 0.9 : 0.5;
  EXPECT_GE(pane.glass_right, want * pane.total) << pane.glass_right << " / " << pane.total;
  // Walls seen from many angles: occupied, hardly any glass.
  const Tally top = tallyLine(e, {1.0, 6.0 - 1e-3}, {4.5, 6.0 - 1e-3}, 18);
  EXPECT_GE(top.occ, 0.8 * top.total) << top.occ << " / " << top.total;
  const Tally side = tallyLine(e, {6.0, 6.0 - 1e-3}, {9.5, 6.0 - 1e-3}, 18);
  EXPECT_GE(side.occ, 0.8 * side.total);
  // Glass cells away from the pane are few.
  std::size_t far_glass = 0;
  for (std::size_t i = 0; i < e.label.size(); ++i) {
    if (!isGlass(e.label[i])) continue;
    const Vec2 p = e.geometry.center(e.geometry.cellOf(i).x, e.geometry.cellOf(i).y);
    if (std::abs(p.x() - 5.0) > 0.15) ++far_glass;
  }
  EXPECT_LE(far_glass, GetParam() == Method::Direct ? 10U : 60U);
}

INSTANTIATE_TEST_SUITE_P(Methods, Classifiers, ::testing::Values(Method::Heuristic, Method::Direct),
                         [](const auto& info) { return std::string(toString(info.param)); });

TEST(Direct, CostsAreNormalisedNegativeLogPosteriors) {
  const LaserLog log = synthLog(scene(), 3);
  const MappingResult r = mapLog(log, {});
  const CellEvidence& e = r.evidence;
  ASSERT_GT(e.cells.size(), 0U);
  ASSERT_EQ(e.cost.size(), e.cells.size() * 38U);
  EXPECT_TRUE(std::is_sorted(e.cells.begin(), e.cells.end()));
  for (std::size_t i = 0; i < e.cells.size(); i += 7) {
    double z = 0.0;
    const float* c = e.costs(i);
    for (int l = 0; l < 38; ++l) {
      EXPECT_GE(c[l], 0.0f);
      z += std::exp(-static_cast<double>(c[l]));
    }
    EXPECT_NEAR(z, 1.0, 1e-3);
    EXPECT_EQ(e.label[e.cells[i]], std::min_element(c, c + 38) - c);
    EXPECT_EQ(e.candidate(e.cells[i]), static_cast<std::int64_t>(i));
  }
  EXPECT_GT(r.stats.bytes_per_observed_cell, 0.0);
  EXPECT_LT(r.stats.bytes_per_observed_cell, 64.0);
}

TEST(Direct, CellsNextToGlassMayStandInForItAtTheirEvidenceAgainstIt) {
  const MappingResult r = mapLog(synthLog(scene(), 3), {});
  const CellEvidence& e = r.evidence;
  ASSERT_EQ(e.neutral_cost.size(), e.cells.size());
  const auto& g = e.geometry;
  std::size_t offered = 0, against = 0;
  for (std::size_t i = 0; i < e.cells.size(); ++i) {
    const auto c = g.cellOf(e.cells[i]);
    bool next_to_glass = false;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx)
        if ((dx | dy) != 0 && isGlass(e.label[g.index(c.x + dx, c.y + dy)])) next_to_glass = true;
    const bool expected = next_to_glass && !isGlass(e.label[e.cells[i]]);
    ASSERT_EQ(std::isfinite(e.neutral_cost[i]), expected) << "candidate " << i;
    if (!expected) continue;
    ++offered;
    EXPECT_GE(e.neutral_cost[i], e.costs(i)[kEmpty] - 1e-4f);
    // Some cells beside this pane were seen along its normal and passed: evidence against glass.
    against += e.neutral_cost[i] > e.costs(i)[kEmpty] + 2.0f ? 1 : 0;
  }
  // Measured: 13 offered, 5 of them with more than 2 nats against.
  EXPECT_GE(offered, 8u);
  EXPECT_GE(against, 2u) << against << " of " << offered;
}

// A calibration round changes the lobe only: its pass takes the walks over the beams from the
// last one and labels as a fresh pass would; other beam settings or another log walk again.
TEST(Direct, ALaterPassWithAnotherLobeReusesTheWalksOverTheBeams) {
  const LaserLog log = synthLog(scene(), 3);
  MappingOptions first, wide = first;
  wide.direct.direct_sigma_deg = 8.0;
  wide.direct.direct_peak = 0.5;
  wide.direct.direct_floor = 0.05;
  wide.direct.range_sigma = 0.02;
  BeamPasses walks;
  mapLog(log, first, {}, &walks);
  const MappingResult again = mapLog(log, wide, {}, &walks);
  EXPECT_EQ(walks.reused(), 1);
  EXPECT_EQ(again.stats.seconds_counts, 0.0);
  const MappingResult fresh = mapLog(log, wide);
  EXPECT_EQ(again.evidence.label, fresh.evidence.label);
  EXPECT_EQ(again.evidence.cost, fresh.evidence.cost);
  EXPECT_EQ(again.stats.beams, fresh.stats.beams);
  EXPECT_NE(fresh.evidence.label, mapLog(log, first).evidence.label);  // the lobe made a difference
  // A wider miss margin changes the counts: walked again.
  MappingOptions margin = wide;
  margin.beams.miss_margin = 0.2;
  const MappingResult walked = mapLog(log, margin, {}, &walks);
  EXPECT_EQ(walks.reused(), 1);
  EXPECT_EQ(walked.evidence.label, mapLog(log, margin).evidence.label);
  // Another log with the same options: walked again.
  const LaserLog other = synthLog(scene(), 4);
  const MappingResult theirs = mapLog(other, margin, {}, &walks);
  EXPECT_EQ(walks.reused(), 1);
  EXPECT_EQ(theirs.evidence.label, mapLog(other, margin).evidence.label);
}

// The spurious rate is read from the empty cells away from every surface: hits within the
// clearance of an occupied or glass cell (range noise, a pane's returns) are not counted.
TEST(EmptyHitRate, CountsTheEmptyCellsAwayFromTheSurfaces) {
  grid::GridGeometry g;
  g.width = 20;
  g.height = 12;
  grid::HitMissGrid counts(g);
  CellEvidence e;
  e.geometry = g;
  e.label.assign(g.cells(), kEmpty);
  for (int y = 0; y < g.height; ++y) e.label[g.index(3, y)] = kOccupied;  // a wall along x = 3
  e.label[g.index(15, 6)] = glassLabel(4);                                // a pane cell
  e.label[g.index(10, 0)] = kUnknown;
  std::uint64_t hits = 0, misses = 0;
  std::size_t cells = 0;
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      grid::CellCounts& c = counts.at(x, y);
      c.hits = static_cast<std::uint16_t>((x + y) % 3);
      c.misses = static_cast<std::uint16_t>(100 + x);
      const bool near_wall = std::abs(x - 3) <= 2, near_pane = std::abs(x - 15) <= 2 && std::abs(y - 6) <= 2;
      if (near_wall || near_pane || (x == 10 && y == 0)) continue;
      hits += c.hits;
      misses += c.misses;
      ++cells;
    }
  const EmptyHitRate r = emptyHitRate(counts, e, 2);
  EXPECT_EQ(r.hits, hits);
  EXPECT_EQ(r.misses, misses);
  EXPECT_EQ(r.cells, cells);
  EXPECT_DOUBLE_EQ(r.rate(), static_cast<double>(hits) / static_cast<double>(hits + misses));
  EXPECT_DOUBLE_EQ(r.laplaceRate(), (static_cast<double>(hits) + 1.0) / static_cast<double>(hits + misses + 2));
  EXPECT_DOUBLE_EQ(EmptyHitRate{}.laplaceRate(), 0.5);
  // No clearance: every EMP cell.
  EXPECT_EQ(emptyHitRate(counts, e, 0).cells, g.cells() - static_cast<std::size_t>(g.height) - 2);
}

// With p_hit_emp_from_log the classifier runs again with the rate of the hits the
// first classification's empty space holds: the labels a fixed rate of that value gives.
TEST(Direct, TakesTheSpuriousRateFromTheLogsEmptySpace) {
  LaserLog log = synthLog(scene(), 6);
  // Spurious short readings, one beam in 200, anywhere along the beam.
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (LaserScan& scan : log.scans)
    for (float& r : scan.ranges)
      if (u(rng) < 0.005) r = static_cast<float>(0.3 + u(rng) * (r - 0.3));
  MappingOptions fixed;
  MappingOptions estimated = fixed;
  estimated.direct.p_hit_emp_from_log = true;
  const MappingResult a = mapLog(log, fixed), b = mapLog(log, estimated);
  EXPECT_EQ(a.stats.p_hit_emp, fixed.direct.p_hit_emp);
  ASSERT_GT(b.stats.empty.cells, 1000u);
  ASSERT_GT(b.stats.empty.hits, 0u);
  EXPECT_EQ(a.stats.empty.hits, b.stats.empty.hits);  // read from the first classification
  const double laplace = (static_cast<double>(b.stats.empty.hits) + 1.0) /
                         (static_cast<double>(b.stats.empty.hits + b.stats.empty.misses) + 2.0);
  EXPECT_DOUBLE_EQ(b.stats.p_hit_emp, laplace);
  EXPECT_LT(b.stats.p_hit_emp, 0.01);  // far below the default 0.02: a spurious reading lands in any of ~100 cells
  MappingOptions same = fixed;
  same.direct.p_hit_emp = b.stats.p_hit_emp;
  EXPECT_EQ(mapLog(log, same).evidence.label, b.evidence.label);
  EXPECT_NE(a.evidence.label, b.evidence.label);
  // The pane stays glass at its angle.
  const Tally t = tallyLine(b.evidence, {5.0, 1.7}, {5.0, 4.3}, 0);
  EXPECT_GE(t.glass_right, t.total * 8 / 10);
}

// The robot passes a run's normal four times, 20 s apart, three near-normal beams a scan at 10 Hz.
// A pane answers every visit at its rate; a person stood there during one visit only, in part of
// each of its beams (a leg, not a wall: each beam on its own, so the within-scan test cannot tell),
// and answered no other visit.
TEST(VisitCoherence, APersonAnswersOneVisitAPaneEvery) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto beams = [&](std::uint32_t run, auto&& rate) {
    std::vector<sparse::NearNormalBeam> out;
    std::uint32_t scan = 0;
    for (int visit = 0; visit < 4; ++visit)
      for (int k = 0; k < 30; ++k, ++scan)
        for (int b = 0; b < 3; ++b)
          out.push_back({run, scan, 0.01f * static_cast<float>(b), u(rng) < rate(visit, k), 20.0 * visit + 0.1 * k});
    return out;
  };
  std::vector<sparse::NearNormalBeam> near = beams(0, [](int, int) { return 0.3; });
  const auto person = beams(1, [](int visit, int) { return visit == 2 ? 0.2 : 0.0; });
  near.insert(near.end(), person.begin(), person.end());
  const SparsePaneOptions o;
  const double bin = deg2rad(o.lobe_bin_deg);
  const std::vector<sparse::ScanCoherence> scans = sparse::scanCoherence(near, 2, bin);
  const std::vector<sparse::ScanCoherence> visits = sparse::visitCoherence(near, 2, bin, o.max_visit_gap_s);
  EXPECT_EQ(visits[0].scans, 4u);
  EXPECT_EQ(visits[1].scans, 4u);
  EXPECT_FALSE(sparse::isTransient(scans[1], o.max_transient_p, o.min_transient_correlation))
      << scans[1].z << " " << scans[1].correlation;
  EXPECT_FALSE(sparse::isTransient(visits[0], o.max_transient_p, o.min_visit_correlation))
      << visits[0].z << " " << visits[0].correlation;
  EXPECT_TRUE(sparse::isTransient(visits[1], o.max_transient_p, o.min_visit_correlation))
      << visits[1].z << " " << visits[1].correlation;
  std::printf(
      "within scans: pane z %.2f, person z %.2f (corr %.3f); by visit: pane z %.2f (corr %.3f), person z %.2f "
      "(corr %.3f)\n",
      scans[0].z, scans[1].z, scans[1].correlation, visits[0].z, visits[0].correlation, visits[1].z,
      visits[1].correlation);
  // One visit: nothing to compare (its rate is its own).
  const std::vector<sparse::NearNormalBeam> once(person.begin() + 180, person.begin() + 270);
  EXPECT_FALSE(sparse::isTransient(sparse::visitCoherence(once, 2, bin, o.max_visit_gap_s)[1], o.max_transient_p, 0.0));
}

// One visit: the robot passes a 2 m run at 0.5 m/s, 10 Hz, 15 near-normal beams a scan 8 cm apart
// about its foot on the run. A pane answers each beam at its rate; a person walks along the run at
// 1.2 m/s, 0.4 m wide, and answers the beams that meet it. Its scans' beams meet more of the line
// than the person, so within scans it correlates too little for a transient; at one place moments
// apart it answers scan after scan.
TEST(PlaceCoherence, APersonWalkingAlongTheRunAnswersItsPlaceScanAfterScan) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto beams = [&](std::uint32_t run, auto&& returns) {
    std::vector<sparse::NearNormalBeam> out;
    for (std::uint32_t scan = 0; scan < 40; ++scan) {
      const double t = 0.1 * scan, foot = 0.5 * t;
      for (int b = -7; b <= 7; ++b) {
        const double along = foot + 0.08 * b;
        if (along < 0.0 || along > 2.0) continue;
        const auto incidence = static_cast<float>(std::abs(0.08 * b) / 6.0);  // the run 6 m off
        out.push_back({run, scan, incidence, returns(t, along), t, static_cast<float>(along)});
      }
    }
    return out;
  };
  std::vector<sparse::NearNormalBeam> near = beams(0, [&](double, double) { return u(rng) < 0.5; });
  const auto person =
      beams(1, [&](double t, double along) { return std::abs(along - (1.2 * t - 0.7)) <= 0.2 && u(rng) < 0.9; });
  near.insert(near.end(), person.begin(), person.end());
  const SparsePaneOptions o;
  const double bin = deg2rad(o.lobe_bin_deg);
  const std::vector<sparse::ScanCoherence> scans = sparse::scanCoherence(near, 2, bin);
  const std::vector<sparse::ScanCoherence> place =
      sparse::placeCoherence(near, 2, bin, o.max_place_dt_s, o.max_place_ds);
  EXPECT_FALSE(sparse::isTransient(scans[0], o.max_transient_p, o.min_transient_correlation));
  EXPECT_FALSE(sparse::isTransient(scans[1], o.max_one_visit_transient_p, o.min_transient_correlation))
      << scans[1].z << " " << scans[1].correlation;
  EXPECT_FALSE(sparse::isTransient(place[0], o.max_one_visit_transient_p, o.min_transient_correlation))
      << place[0].z << " " << place[0].correlation;
  EXPECT_TRUE(sparse::isTransient(place[1], o.max_transient_p, o.min_transient_correlation))
      << place[1].z << " " << place[1].correlation;
  EXPECT_GT(place[1].scans, 100u);  // pairs
  // Pairs only within the time window: none with a window shorter than a scan, and none between
  // scans stamped alike (a log without times).
  EXPECT_EQ(sparse::placeCoherence(near, 2, bin, 0.05, o.max_place_ds)[1].scans, 0u);
  std::vector<sparse::NearNormalBeam> untimed = near;
  for (sparse::NearNormalBeam& b : untimed) b.time = 0.0;
  EXPECT_EQ(sparse::placeCoherence(untimed, 2, bin, o.max_place_dt_s, o.max_place_ds)[1].scans, 0u);
  std::printf(
      "within scans: pane %.3f (z %.2f), person %.3f (z %.2f); at one place: pane %.3f (z %.2f), person %.3f "
      "(z %.2f)\n",
      scans[0].correlation, scans[0].z, scans[1].correlation, scans[1].z, place[0].correlation, place[0].z,
      place[1].correlation, place[1].z);
}

TEST(Direct, WallOnlySceneHasNoGlass) {
  VectorMap map = scene();
  for (auto& s : map.segments) s.material = Material::Wall;
  const MappingResult r = mapLog(synthLog(map, 5), {});
  EXPECT_LE(r.stats.glass_cells, 3U);
  EXPECT_GT(r.stats.occupied_cells, 200U);
}

}  // namespace
}  // namespace glassmap::glass
