// End to end on the bundled scenes: simulate (fixed seed) -> pipeline::mapLog with its defaults,
// as `glassmap map` runs it (direct classifier, MRF, mirror-phantom test, vectorisation with the
// structure step, pane fit) -> score the floorplan's walls and glass against the scene's structure
// (its walls and glass; the desks, outlines 0.08 m thick, are furniture and belong in the clutter
// layer); then simulate again on the mapped floorplan (read back from GPKG). Thresholds sit just
// under the figures reached on 2026-11-25 (glass F1 / wall F1 at 0.10 m): paper-corridor
// 0.95 / 0.88, glass-corridor 1.00 / 0.94, office-floor 0.92 / 0.94, no-glass - / 0.98 (against
// the whole plan, desks included, before the structure step: 0.84 / 0.90 / 0.92 / 0.94). Wall
// recall falls short where the robot never saw a wall (paper-corridor's far rooms); against the
// walls in line of sight of some laser pose, wall F1 is 0.95 / 0.94 / 0.94 / 0.98. Of the desks'
// outlines 0-11% lies in the walls. The clutter layer holds the lines that explain the returns the
// walls leave (vector/scan_clutter.hpp: each at least 1e-3 of the returns): 32% / 60% / 4% / 36% of
// the desks' outlines (37-57% when it held every occupied blob's outline). On office-floor
// (2.2 million returns, 99.1% of them explained by the walls and the cells' clutter) most desk
// sides are hit by fewer than 2,000 returns: two lines replace the cells' 23 pieces there.
#include <gtest/gtest.h>

#include <algorithm>

#include <filesystem>
#include <iostream>

#include "glassmap/eval/cells.hpp"
#include "glassmap/eval/segments.hpp"
#include "glassmap/eval/visibility.hpp"
#include "glassmap/io/floorplan.hpp"
#include "glassmap/pipeline/map_log.hpp"
#include "glassmap/sim/scene.hpp"
#include "glassmap/sim/simulator.hpp"
#include "glassmap/vector/export.hpp"

namespace glassmap::vector {
namespace {

struct Expectation {
  const char* scene;
  double min_glass_f1;  // at 0.10 m
  double max_oversegmentation;
  double min_wall_f1;
  double min_seen_wall_f1;      // recall against the walls some laser pose had in line of sight
  double min_desks_as_clutter;  // recall of the desks' outlines by the clutter layer
  int passes;                   // mapping passes: 1 when the lobe fitted on the first agrees with its lobe
};

class SceneE2E : public ::testing::TestWithParam<Expectation> {};

// Simulates `scene` (seed 1) and maps it with the pipeline's defaults (optionally without the
// pane fit of the cells).
struct Mapped {
  sim::SimResult run;
  pipeline::MapResult mapped;
};
Mapped simulateAndMap(const sim::Scene& scene, bool prune_unfitted_glass = true) {
  sim::SimOptions so;
  so.seed = 1;
  Mapped m{sim::simulate(scene, so), {}};
  pipeline::MapOptions options;
  options.prune_unfitted_glass = prune_unfitted_glass;
  m.mapped = pipeline::mapLog(m.run.log, options);
  return m;
}

sim::Scene bundledScene(const std::string& name) {
  return sim::loadScene(std::filesystem::path(GLASSMAP_SOURCE_DIR) / "maps" / name / "scene.yaml");
}

TEST_P(SceneE2E, FloorplanMatchesTheScene) {
  const Expectation& x = GetParam();
  const sim::Scene scene = bundledScene(x.scene);
  const Mapped m = simulateAndMap(scene);
  const sim::SimResult& run = m.run;
  EXPECT_TRUE(m.mapped.has_floorplan);
  // The scenes' laser has the prior's lobe (2 deg, peak 0.9). Where the lobe fitted against the
  // first pass agrees with it within its standard errors (office-floor: 0.898 +- 0.004, 2.01 +-
  // 0.01 deg), the first pass is the map and the profile keeps the lobe it was made with; on the
  // corridors the first pass's panes give a fit further off than its errors (40 s of
  // paper-corridor: peak 0.83 +- 0.01), and a second pass maps with it. No glass: nothing to fit.
  const pipeline::MapResult& r = m.mapped;
  EXPECT_EQ(r.passes, x.passes);
  if (r.passes == 1 && r.calibration.profile.direct_sigma_deg.fitted) {
    const SensorProfile& fit = r.calibration.profile;
    EXPECT_LE(std::abs(fit.direct_sigma_deg.value - 2.0), fit.direct_sigma_deg.se);
    EXPECT_LE(std::abs(fit.direct_peak.value - 0.9), fit.direct_peak.se);
    EXPECT_EQ(r.profile.direct_sigma_deg.value, 2.0);
    EXPECT_EQ(r.profile.direct_peak.value, 0.9);
    EXPECT_EQ(r.profile.direct_floor.value, 0.0);
    EXPECT_TRUE(std::any_of(r.calibration.warnings.begin(), r.calibration.warnings.end(), [](const std::string& w) {
      return w.find("agrees with the first pass") != std::string::npos;
    }));
    // The profile maps the map again.
    pipeline::MapOptions given;
    given.sensor = r.profile;
    EXPECT_EQ(pipeline::mapLog(m.run.log, given).evidence.label, r.evidence.label);
  }
  const VectorizeResult& v = m.mapped.floorplan;
  // The building is the scene's walls and glass; its desks (outlines 0.08 m thick) are furniture,
  // which the plan keeps in its clutter layer, out of the walls.
  VectorMap structure, desks;
  for (const MapSegment& s : scene.map.segments)
    (s.material == Material::Wall && s.thickness < 0.1 ? desks : structure).segments.push_back(s);
  const eval::SegmentEvalResult e = eval::evaluateSegments(structure, v.map);
  std::cout << x.scene << ": glass P " << e.glass.precision << " R " << e.glass.recall << " F1 " << e.glass.f1 << ", "
            << e.glass.pred_segments << "/" << e.glass.truth_segments << " segments, " << e.segments_per_found_pane
            << " per found pane, angle error " << e.glass_angle_error_deg << " deg; wall P " << e.wall.precision
            << " R " << e.wall.recall << " F1 " << e.wall.f1 << "; vectorised in " << v.stats.seconds << " s\n";
  EXPECT_GE(e.wall.f1, x.min_wall_f1);
  const double desks_as_walls = eval::evaluateSegments(desks, v.map).wall.recall;
  const double desks_as_clutter = eval::evaluateSegments(desks, v.extras.clutter).wall.recall;
  std::cout << x.scene << ": desk outline length found in the walls " << desks_as_walls << ", in the clutter layer "
            << desks_as_clutter << "\n";
  EXPECT_LE(desks_as_walls, 0.15);
  EXPECT_GE(desks_as_clutter, x.min_desks_as_clutter);
  const VectorMap seen = eval::visiblePart(structure, eval::viewpointsOfLog(run.log));
  const double seen_recall = eval::evaluateSegments(seen, v.map).wall.recall;
  const double seen_f1 = 2 * e.wall.precision * seen_recall / (e.wall.precision + seen_recall);
  std::cout << x.scene << ": wall recall over the truth seen from the log " << seen_recall << ", F1 " << seen_f1
            << "\n";
  EXPECT_GE(seen_f1, x.min_seen_wall_f1);

  // The mapped floorplan, written as GPKG and read back, drives a simulation in turn.
  const std::filesystem::path gpkg =
      std::filesystem::temp_directory_path() / (std::string("glassmap_e2e_") + x.scene + ".gpkg");
  exportFloorplan(gpkg, v.map);
  sim::Scene from_map = scene;
  from_map.map = readFloorplan(gpkg);
  std::filesystem::remove(gpkg);
  EXPECT_EQ(from_map.map.segments.size(), v.map.segments.size());
  sim::SimOptions brief;
  brief.seed = 2;
  brief.duration_limit = 2.0;
  const sim::SimResult again = sim::simulate(from_map, brief);
  EXPECT_GT(again.log.scans.size(), 10u);

  if (e.glass.truth_segments == 0) {
    for (const MapSegment& s : v.map.segments)
      if (s.material == Material::Glass) {
        EXPECT_LE(s.length(), 0.5) << s.a.transpose() << " -> " << s.b.transpose();
      }
    return;
  }
  EXPECT_GE(e.glass.f1, x.min_glass_f1);
  EXPECT_LE(e.oversegmentation, x.max_oversegmentation);
  EXPECT_LE(e.segments_per_found_pane, 1.5);
  EXPECT_LT(e.glass_angle_error_deg, 2.0);
}

// People walking through paper-corridor (5 per 100 m^2): each person seen from one side leaves an
// arc of cells that look like glass facing the robot. The pane fit removes them from the cells.
// Measured (seed 1): glass cell F1 at 2 cells 0.63 without the fit, 0.91 with it (precision 0.48 -> 0.94;
// 0.98 before the vectorizer worked in the grid frame: a borderline pane fit through a passer-by;
// with --profile-lobe 0.915: people block beams, and the fitted lobe peak is 0.86, not 0.9;
// 0.914 with the pane Psi, which charges the arcs' across-pane borders nothing; 0.900, precision
// 0.899 and recall 0.902 (0.924 before the fit), since the classifier expects per cell the share
// of a pane's returns that land in it (glass/classifiers.hpp, PaneLanding): the arcs seen
// obliquely pass for glass more often, 0.44 of the cells before the fit against 0.50); 0.885,
// precision 0.899 and recall 0.871 (0.896 before the fit), since a beam through a one-cell gap in
// a pane's labels counts as gone through it (glass/opaque_glass.hpp): beams past the people's arcs
// no longer cross the panes behind them directly, and a few pane cells pass for opaque; 0.883,
// precision 0.898, recall 0.869, since the classifier takes the fitted lobe (peak 0.86 here: people
// block beams that would have returned; pipeline/map_log.hpp, profile_lobe) and the range noise
// (0.878 and 0.887 with the lobe alone).
TEST(PeopleE2E, PassersByDoNotBecomeGlassCells) {
  sim::Scene scene = bundledScene("paper-corridor");
  scene.people.density = 5.0;
  const glass::CellEvidence raw = simulateAndMap(scene, false).mapped.evidence;
  const Mapped m = simulateAndMap(scene);
  const glass::CellEvidence& e = m.mapped.evidence;
  const std::size_t pruned = m.mapped.pruned_glass;
  const eval::CellEvalResult before = eval::evaluateCells(scene.map, raw.geometry, raw.label, raw.bins);
  const eval::CellEvalResult after = eval::evaluateCells(scene.map, e.geometry, e.label, e.bins);
  EXPECT_GT(pruned, 0u);
  std::cout << "people 5: glass cells P@2/R@2/F1@2 " << before.tolerant.precision << "/" << before.tolerant.recall
            << "/" << before.tolerant.f1 << " -> " << after.tolerant.precision << "/" << after.tolerant.recall << "/"
            << after.tolerant.f1 << " (" << pruned << " cells relabelled)\n";
  EXPECT_LT(before.tolerant.precision, 0.7);
  EXPECT_GE(after.tolerant.precision, 0.88);
  EXPECT_GE(after.tolerant.f1, 0.87);
  EXPECT_GE(after.tolerant.recall, before.tolerant.recall - 0.03);
}

INSTANTIATE_TEST_SUITE_P(Scenes, SceneE2E,
                         ::testing::Values(Expectation{"paper-corridor", 0.92, 1.5, 0.85, 0.93, 0.28, 2},
                                           Expectation{"glass-corridor", 0.95, 0.5, 0.92, 0.92, 0.45, 2},
                                           // office-floor's glass: 0.920 at stop 41, 0.898 at stop 42
                                           // (a false pane outside the facade, a mirror image seen
                                           // past the end of the facade's run of returns), 0.926
                                           // since the runs' lines catch it (docs/calibration.md)
                                           Expectation{"office-floor", 0.90, 1.0, 0.91, 0.92, 0.03, 1},
                                           Expectation{"no-glass", 0.0, 0.0, 0.95, 0.95, 0.30, 1}),
                         [](const auto& info) {
                           std::string n = info.param.scene;
                           for (char& c : n)
                             if (c == '-') c = '_';
                           return n;
                         });

}  // namespace
}  // namespace glassmap::vector
