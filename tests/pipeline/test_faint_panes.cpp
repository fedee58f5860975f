// `glassmap map` (every step, by default) on panes seen by a faint, mirror-like laser (the glass
// response of the random:7 profile: a return at normal incidence 53% of the time, lobe sigma
// 3.6 deg, 6% at any angle, 86% of the other beams reflected) around the glass meeting room of
// maps/glass-room, turned 25 deg in the grid; and random:20 below, in the glass room and corridor.
// A pane cell sees only a share of the pane's returns (glass/classifiers.hpp, PaneLanding): a
// classifier that expected the lobe's rate in every cell labelled none of the room's panes (cell
// F1@2 0.15 in tools/sensor_sweep.py).
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "glassmap/pipeline/map_log.hpp"
#include "glassmap/sim/scene.hpp"
#include "glassmap/sim/sensor_profile.hpp"
#include "glassmap/sim/simulator.hpp"

namespace glassmap::pipeline {
namespace {

// Distance from p to the nearest pane of `plan`, its ends trimmed by `trim` [m].
double paneDistance(const VectorMap& plan, const Vec2& p, double trim) {
  double best = 1e9;
  for (const MapSegment& s : plan.segments) {
    if (s.material != Material::Glass) continue;
    const Vec2 d = s.b - s.a;
    const double len = d.norm();
    const double t = std::clamp((p - s.a).dot(d) / len, trim, len - trim);
    best = std::min(best, (p - (s.a + d * (t / len))).norm());
  }
  return best;
}

struct PaneCells {
  std::size_t on = 0;         ///< cells on a pane's line, 0.3 m from its ends
  std::size_t on_glass = 0;   ///< ... with a glass cell within 2 cells (as cell F1@2 counts recall)
  std::size_t off_glass = 0;  ///< glass cells more than 3 cells from every pane
};

PaneCells countPaneCells(const VectorMap& truth, const glass::CellEvidence& e) {
  const grid::GridGeometry& g = e.geometry;
  PaneCells n;
  std::vector<Vec2> glass_cells;
  for (int y = 0; y < g.height; ++y) {
    for (int x = 0; x < g.width; ++x) {
      if (!isGlass(e.label[g.index(x, y)])) continue;
      glass_cells.push_back(g.center(x, y));
      if (paneDistance(truth, g.center(x, y), 0.0) > 3 * g.resolution) ++n.off_glass;
    }
  }
  for (int y = 0; y < g.height; ++y) {
    for (int x = 0; x < g.width; ++x) {
      const Vec2 p = g.center(x, y);
      if (paneDistance(truth, p, 0.3) > 0.5 * g.resolution) continue;
      ++n.on;
      for (const Vec2& q : glass_cells) {
        if ((q - p).norm() <= 2 * g.resolution + 1e-9) {
          ++n.on_glass;
          break;
        }
      }
    }
  }
  std::printf("%zu of %zu pane cells glass, %zu glass cells elsewhere\n", n.on_glass, n.on, n.off_glass);
  return n;
}

// A bundled scene simulated with a sensor profile at 10 Hz, as tools/sensor_sweep.py does.
struct Simulated {
  sim::Scene scene;
  LaserLog log;
};

// `edit` changes the scene (its map, its trajectory) before it is simulated.
Simulated simulateWith(const char* laser, const char* scene_name, std::uint64_t seed = 1,
                       const std::function<void(sim::Scene&)>& edit = {}) {
  Simulated s;
  s.scene = sim::loadScene(std::filesystem::path(GLASSMAP_SOURCE_DIR) / "maps" / scene_name / "scene.yaml");
  sim::applySensorProfile(s.scene, sim::sensorProfile(laser));
  s.scene.laser.rate = 10.0;
  if (edit) edit(s.scene);
  sim::SimOptions so;
  so.seed = seed;
  s.log = sim::simulate(s.scene, so).log;
  return s;
}

// maps/glass-room (the room turned 25 deg in its hall) with the room, its table and the robot's
// loop around it turned `degrees` more about the room's centre (7, 6): tools/sensor_sweep.py's
// glass-room@ANGLE for ANGLE = 25 + degrees. The hall's walls and desks stay.
Simulated simulateTurnedGlassRoom(const char* laser, double degrees, std::uint64_t seed) {
  return simulateWith(laser, "glass-room", seed, [degrees](sim::Scene& scene) {
    const Vec2 centre(7.0, 6.0);
    const Eigen::Rotation2Dd turn(deg2rad(degrees));
    auto turned = [&](const Vec2& p) -> Vec2 { return centre + turn * (p - centre); };
    for (MapSegment& seg : scene.map.segments)
      if ((seg.a - centre).norm() < 3.5 && (seg.b - centre).norm() < 3.5) {
        seg.a = turned(seg.a);
        seg.b = turned(seg.b);
      }
    for (Vec2& w : scene.trajectory.waypoints) w = turned(w);
  });
}

struct Case {
  const char* laser;
  const char* scene;
};

class FaintPanes : public ::testing::TestWithParam<Case> {};

TEST_P(FaintPanes, AreGlassAlongTheirLengthAndNothingElseIs) {
  const Simulated s = simulateWith(GetParam().laser, GetParam().scene);
  const MapResult r = mapLog(s.log);
  const PaneCells n = countPaneCells(s.scene.map, r.evidence);
  EXPECT_GE(n.on_glass, 0.7 * static_cast<double>(n.on));
  EXPECT_LE(static_cast<double>(n.off_glass), 0.1 * static_cast<double>(n.on));
}

// random:16 (peak 0.3, sigma 11.6 deg, 13% at any angle: its panes return 9-20% of the beams)
// around the glass room. At stop 33 the first pass, with the default 2 deg / 0.9 lobe and no range
// noise, called no cell glass, and only a second pass with a broad search lobe (lobe_search) found
// the panes to fit the lobe against (cell F1@2 0 -> 0.83). The first pass now has the range noise
// of the log (sensor::inScanNoise; random:16's grows with range, 1% of it): it finds the panes
// itself, the lobe is fitted against them, and the last pass maps with it; the default lobe finds
// far fewer of the pane cells.
TEST(FaintPanes, AFirstPassThatKnowsTheNoiseFindsTheLobeOfAFaintLaser) {
  const Simulated s = simulateWith("random:16", "glass-room");
  const MapResult r = mapLog(s.log);
  ASSERT_TRUE(r.profile.direct_sigma_deg.fitted);
  EXPECT_NEAR(r.profile.direct_sigma_deg.value, 11.6, 0.25 * 11.6);
  EXPECT_TRUE(std::none_of(r.calibration.warnings.begin(), r.calibration.warnings.end(),
                           [](const std::string& w) { return w.find("broad lobe") != std::string::npos; }));
  MapOptions default_lobe;
  default_lobe.profile_lobe = false;
  const MapResult was_map = mapLog(s.log, default_lobe);
  const PaneCells was = countPaneCells(s.scene.map, was_map.evidence);
  const PaneCells n = countPaneCells(s.scene.map, r.evidence);
  EXPECT_GE(n.on_glass, 0.6 * static_cast<double>(n.on));
  EXPECT_GE(n.on_glass, was.on_glass + n.on / 5);
  EXPECT_LE(static_cast<double>(n.off_glass), 0.1 * static_cast<double>(n.on));
}

// random:102 (peak 0.42, lobe sigma 3.7 deg, 5% at any angle, 69% of the other beams reflected
// whatever the angle) around the glass room, simulated with seed 7: the robot circles the room, so
// each pane is met near its normal from its own side and, across the room, through the pane
// opposite, which folds most of those beams away. Counted as the pane's own beams, those visits
// answered hardly ever (0.01 against 0.35 from its side), and the sparse-pane search refused every
// pane as a passer-by (cell F1@2 0.0 in tools/sensor_sweep.py --seed 7). The visit test now leaves
// out the near-normal beams another candidate folded first (mirrored back across its line, their
// readings fall on a wall).
TEST(FaintPanes, APaneIsJudgedByTheBeamsThatReachedItFirst) {
  const Simulated s = simulateWith("random:102", "glass-room", 7);
  const MapResult r = mapLog(s.log);
  const PaneCells n = countPaneCells(s.scene.map, r.evidence);
  std::printf("sparse panes: %zu (%.1f m); rejected %zu by visit\n", r.sparse.panes, r.sparse.metres,
              r.sparse.rejected_one_visit);
  EXPECT_GE(n.on_glass, 0.9 * static_cast<double>(n.on));
  EXPECT_LE(static_cast<double>(n.off_glass), 0.1 * static_cast<double>(n.on));
}

// Maps `s` with the defaults: at least 90% of its pane cells glass, glass elsewhere on at most a
// tenth as many cells.
void expectPanesFound(const Simulated& s) {
  const MapResult r = mapLog(s.log);
  const PaneCells n = countPaneCells(s.scene.map, r.evidence);
  std::printf("sparse panes: %zu (%.1f m); rejected %zu without a lobe, %zu through another pane\n", r.sparse.panes,
              r.sparse.metres, r.sparse.rejected_unspecific, r.sparse.rejected_through);
  EXPECT_GE(n.on_glass, 0.9 * static_cast<double>(n.on));
  EXPECT_LE(static_cast<double>(n.off_glass), 0.1 * static_cast<double>(n.on));
}

// random:112 (peak 0.41, lobe sigma 3.1 deg, 7% at any angle, 90% of the other beams reflected)
// around the glass room, seed 7. Its panes answer the many beams that meet them off the normal
// more often in all than the few near it, so the sparse-pane search's old per-cell test (60% of a
// cell's returns within 10 deg of the line's normal) kept 15-17 of a pane's 90 cells and no pane
// stood out from chance; the classifiers found nothing and the calibration fitted a 20 deg lobe
// (cell F1@2 0.0 in tools/sensor_sweep.py --seed 7, also with the true profile). The search now
// compares rates per run: near the normal a pane answers 0.22-0.25 of its beams, at other angles
// 0.05. And the reflections of the table in the room, seen across it in the far pane, land as
// phantom glass on the near side, where the robot drives: the test "seen through another pane"
// no longer counts glass that is the run's own mirror image.
TEST(FaintPanes, APaneThatAnswersEveryAngleNowAndThenIsFoundByItsLobe) {
  expectPanesFound(simulateWith("random:112", "glass-room", 7));
}

// The same laser around the room turned 37 deg (glass-room@37 in the sweep), seed 7: beside the
// lobe, one pane needs the second step. The table's phantoms seen across the room in it cover the
// ground the robot drives on before it, and the pane's own returns crossed them.
TEST(FaintPanes, APanesOwnPhantomsInFrontOfItAreNoPaneItIsSeenThrough) {
  expectPanesFound(simulateTurnedGlassRoom("random:112", 12.0, 7));
}

// random:30 (peak 0.50, lobe sigma 2.6 deg, 9% at any angle, 2.2 cm noise + 0.9% of the range)
// around the glass room: its panes return near their normal only, from a few of the robot's
// poses, so the direct classifier finds one pane cell in three or four; the others have the
// hits of any angle, about as many as an empty cell's spurious ones, and are called EMP on the
// prior. The MRF charged every glass cell for them and emptied the panes (cell F1@2 0.60 against
// the direct classifier's 0.90, tools/sensor_sweep.py); such a gap now stands in for the pane's
// unseen glass at its evidence against it (CellEvidence::neutral_cost).
TEST(FaintPanes, TheMrfKeepsAPaneTheClassifierFoundInOneCellOfSeveral) {
  const Simulated s = simulateWith("random:30", "glass-room");
  // The MRF alone: since stop 53 the sparse-pane search finds these panes itself after it.
  MapOptions mrf_only;
  mrf_only.sparse_panes = false;
  const MapResult r = mapLog(s.log, mrf_only);
  MapOptions charged = mrf_only;
  charged.mrf.candidates_neutral = false;
  const MapResult was_map = mapLog(s.log, charged);
  const PaneCells n = countPaneCells(s.scene.map, r.evidence);
  const PaneCells was = countPaneCells(s.scene.map, was_map.evidence);
  // Measured: 216 of 216 pane cells with a glass cell within 2 cells, 140 with the gaps charged
  // (stop 44, with the search: 131 and 81).
  EXPECT_GE(n.on_glass, 0.5 * static_cast<double>(n.on));
  EXPECT_GE(n.on_glass, was.on_glass + n.on / 10);
  EXPECT_LE(static_cast<double>(n.off_glass), 0.1 * static_cast<double>(n.on));
}

// maps/<name> with `laser`'s profile (the scene's own laser: none) at 10 scans/s and 5 people per
// 100 m^2 walking.
sim::Scene peopleScene(const char* name, const char* laser = nullptr) {
  sim::Scene scene = sim::loadScene(std::filesystem::path(GLASSMAP_SOURCE_DIR) / "maps" / name / "scene.yaml");
  if (laser) sim::applySensorProfile(scene, sim::sensorProfile(laser));
  scene.laser.rate = 10.0;
  scene.people.density = 5.0;
  return scene;
}

LaserLog simulateLog(const sim::Scene& scene, std::uint64_t seed) {
  sim::SimOptions so;
  so.seed = seed;
  return sim::simulate(scene, so).log;
}

// The search (opt-in) on a glass-free floor with 5 people per 100 m^2 (seed 1, as
// tools/sensor_sweep.py --people 5 --seed 1 simulates it). The first pass draws glass only on
// people, which the calibration leaves out; the broad lobe's pass then draws what people left. Until
// stop 49 that was mostly runs across the corridor that return 1-2% near their normal (refused since
// by SparsePaneOptions::min_normal_rate); until stop 50 a person walking along a line in one visit,
// and a lobe fitted to it (peak 0.30 +- 0.13). Since stop 51 the sparse-pane search refuses that run
// too (its beams answer at one place scan after scan: placeCoherence), the broad pass finds no
// glass to fit, and the map keeps the default lobe. Either way the user gets no glass in the map.
TEST(FaintPanes, TheSearchDrawsNoGlassOfPeopleOnAGlassFreeFloor) {
  const LaserLog log = simulateLog(peopleScene("no-glass"), 1);
  MapOptions search;
  search.lobe_search = true;
  const MapResult r = mapLog(log, search);
  for (const std::string& w : r.calibration.warnings) std::printf("warning: %s\n", w.c_str());
  std::printf("passes %d; lobe peak %.3f +- %.3f, sigma %.2f deg\n", r.passes, r.profile.direct_peak.value,
              r.profile.direct_peak.se, r.profile.direct_sigma_deg.value);
  // The search mapped again with the broad lobe (and says what it found).
  EXPECT_TRUE(std::any_of(r.calibration.warnings.begin(), r.calibration.warnings.end(), [](const std::string& w) {
    return w.find("a pass with a broad lobe") != std::string::npos;
  }));
  EXPECT_EQ(r.evidence.countGlass(), 0u);
  EXPECT_TRUE(std::none_of(r.floorplan.map.segments.begin(), r.floorplan.map.segments.end(),
                           [](const MapSegment& s) { return s.material == Material::Glass; }));
  // A lobe the search fitted is either refused or kept with the error that says how little it rests on.
  if (r.profile.direct_peak.value != SensorProfile{}.direct_peak.value) {
    EXPECT_TRUE(r.profile.direct_peak.fitted);
    EXPECT_GT(r.profile.direct_peak.se, 0.25 * r.profile.direct_peak.value);
  }
}

// rplidar-a2 (peak 0.3, lobe sigma 1 deg) around the glass room with 5 people per 100 m^2, seed 2
// (tools/sensor_sweep.py --profiles rplidar-a2 --people 5 --seed 2): the sparse-pane search kept
// four runs people drew outside the room (1.4-1.9 m; their beams' within-scan correlation 0.10-0.16,
// under the 0.25 the scan test asks), the lobe was fitted to them (5.9 deg / 0.15) and the map drew
// 140 glass cells, none on a pane. The robot passes each run's normal several times; a person
// answered one pass only (by visit z 22-38, correlation 0.06-0.09; the room's panes in seed 1:
// z -0.5 to 2.1, correlation 0.004 at most): SparsePaneOptions::max_visit_gap_s.
TEST(FaintPanes, PeopleThatAnsweredOneOfTheRobotsVisitsAreNoPanes) {
  const sim::Scene scene = peopleScene("glass-room", "rplidar-a2");
  const LaserLog log = simulateLog(scene, 2);
  // The search as it was when this test was written (stop 50: a cell's share of returns near the
  // normal, no lobe test per run). Since stop 53 the people's runs along the panes do not form: the
  // pane's own runs take their returns.
  MapOptions then;
  then.sparse.min_specific = 0.6;
  then.sparse.min_lobe_contrast = 0.0;
  const MapResult r = mapLog(log, then);
  MapOptions scans_only = then;
  scans_only.sparse.max_visit_gap_s = 0.0;
  scans_only.opaque.max_transient_p = 0.0;  // nor the opaque step's test of time on the classifiers' panes
  const MapResult was = mapLog(log, scans_only);
  std::printf("runs of one visit %zu; sparse panes %zu, without the visit test %zu\n", r.sparse.rejected_one_visit,
              r.sparse.found.size(), was.sparse.found.size());
  const auto offPanes = [&](const MapResult& m) {
    std::size_t off = 0;
    for (const glass::SparsePane& p : m.sparse.found)
      off += paneDistance(scene.map, 0.5 * (p.a + p.b), 0.0) > 0.3 ? 1 : 0;
    return off;
  };
  EXPECT_GT(r.sparse.rejected_one_visit, 0u);
  EXPECT_EQ(offPanes(r), 0u);
  EXPECT_GT(offPanes(was), 0u);  // what the test takes away
  const PaneCells n = countPaneCells(scene.map, r.evidence), n_was = countPaneCells(scene.map, was.evidence);
  EXPECT_LT(n.off_glass, n_was.off_glass);
}

// sick-lms200 on the glass-free floor with 5 people per 100 m^2, seed 3 (tools/sensor_sweep.py
// --profiles sick-lms200 --people 5 --seed 3 no-glass): the sparse-pane search drew four "panes"
// (1.6 m) where people had walked and the map kept 31 glass cells on two glass segments. Two of
// those runs were seen in one of the robot's visits only (so the visit test could not speak), their
// near-normal beams returning together within scans at z 2.4-2.6 (p 0.004-0.009) and correlation
// 0.31-0.37, short of the 1e-3 the within-scan test asks of any run (the other two: correlation
// 0.22 and 0.25 minus a hair, under the floor; the later steps clear their cells).
// SparsePaneOptions::max_one_visit_transient_p asks p < 0.05 of a run seen in one visit only.
TEST(FaintPanes, PeopleSeenInOneVisitNeedLessToBeTransients) {
  const sim::Scene scene = peopleScene("no-glass", "sick-lms200");
  const LaserLog log = simulateLog(scene, 3);
  const MapResult r = mapLog(log);
  MapOptions strict;
  strict.sparse.max_one_visit_transient_p = 0.0;
  strict.opaque.max_transient_p = 0.0;  // nor the opaque step's test of time on the classifiers' panes
  const MapResult was = mapLog(log, strict);
  const std::size_t off = countPaneCells(scene.map, r.evidence).off_glass;
  const std::size_t off_was = countPaneCells(scene.map, was.evidence).off_glass;
  std::printf("one-visit transients %zu; sparse panes %zu (%.2f m), without the rule %zu (%.2f m)\n",
              r.sparse.rejected_transient_one_visit, r.sparse.found.size(), r.sparse.metres, was.sparse.found.size(),
              was.sparse.metres);
  EXPECT_GT(r.sparse.rejected_transient_one_visit, 0u);
  EXPECT_EQ(was.sparse.rejected_transient_one_visit, 0u);
  EXPECT_LT(r.sparse.metres, was.sparse.metres);
  EXPECT_GT(off_was, 0u);  // what the rule takes away (a glass-free floor: every glass cell is false)
  EXPECT_EQ(off, 0u);
}

// The scene's own laser on the glass-free floor with 5 people per 100 m^2, seed 2
// (tools/sensor_sweep.py --profiles scene --people 5 --seed 2 no-glass): the classifiers took
// people's arcs for panes and the map kept 2.7 m of glass, until the opaque step's test of time
// (glass/opaque_glass.hpp: a person answers all the beams of a scan while there, and one visit).
TEST(FaintPanes, PeopleTheClassifiersTookForPanesAreTransients) {
  const sim::Scene scene = peopleScene("no-glass");
  const LaserLog log = simulateLog(scene, 2);
  const MapResult r = mapLog(log);
  MapOptions untested;
  untested.opaque.max_transient_p = 0.0;
  const MapResult was = mapLog(log, untested);
  const std::size_t off = countPaneCells(scene.map, r.evidence).off_glass;
  const std::size_t off_was = countPaneCells(scene.map, was.evidence).off_glass;
  std::printf("transient panes %zu of %zu (%zu cells); glass cells %zu, without the test %zu\n",
              r.opaque.transient_panes, r.opaque.panes_tested, r.opaque.transient_cells, off, off_was);
  EXPECT_GT(r.opaque.transient_cells, 0u);
  EXPECT_EQ(was.opaque.transient_cells, 0u);
  // What the test takes away (a glass-free floor: every glass cell is false; 18 cells since stop 51,
  // when the sparse-pane search began to refuse a person's run among them itself).
  EXPECT_GT(off_was, 10u);
  EXPECT_EQ(off, 0u);
}

// random:20: peak 0.52, lobe sigma 2.5 deg, 70% of the other beams reflected; its mirror images
// of the room drawn as glass all around it (cell F1@2 0.31) until the opaque-glass test took
// images seen only through other glass for what they are (glass/opaque_glass.hpp). In the glass
// corridor the walls and furniture of the rooms behind the panes passed for glass (F1@2 0.61):
// the straight continuations of the mirrored beams run past them, and those that slipped through
// one-cell gaps in a pane's labels counted as seen directly, until such a gap counted as the pane.
// random:27 (peak 0.42, sigma 2.6 deg, 10% at any angle, 2 cm noise) in the glass corridor, and
// random:4 (peak 0.61, sigma 4.5 deg, 8% at any angle, 2.7 cm noise + 1% of the range) in the
// glass room: cell F1@2 at stop 32 0.50 and 0.81 (tools/sensor_sweep.py); with the fitted lobe
// but without the range noise in the pane share (a noisy laser's returns spread over the cells
// about the pane; a build not kept) 0.53 and 0.69; now 1.00 (with --no-profile-lobe 0.91 and 0.98:
// the noise in the share does most of it here; pipeline/map_log.hpp, applyProfile).
INSTANTIATE_TEST_SUITE_P(Lasers, FaintPanes,
                         ::testing::Values(Case{"random:7", "glass-room"}, Case{"random:20", "glass-room"},
                                           Case{"random:20", "glass-corridor"}, Case{"random:27", "glass-corridor"},
                                           Case{"random:4", "glass-room"}),
                         [](const ::testing::TestParamInfo<Case>& info) {
                           std::string name = std::string(info.param.laser) + "_" + info.param.scene;
                           for (char& c : name)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return name;
                         });

}  // namespace
}  // namespace glassmap::pipeline
