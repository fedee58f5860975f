// `glassmap map` (every step, by default) on panes seen by a faint, mirror-like laser (the glass
// response of the random:7 profile: a return at normal incidence 53% of the time, lobe sigma
// 3.6 deg, 6% at any angle, 86% of the other beams reflected) around the glass meeting room of
// maps/glass-room, turned 25 deg in the grid; and random:20 below, in the glass room and corridor.
// A pane cell sees only a share of the pane's returns (glass/classifiers.hpp, PaneLanding): a
// classifier that expected the lobe's rate in every cell labelled none of the room's panes (cell
// F1@2 0.15 in tools/sensor_sweep.py).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
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

struct Case {
  const char* laser;
  const char* scene;
};

class FaintPanes : public ::testing::TestWithParam<Case> {};

TEST_P(FaintPanes, AreGlassAlongTheirLengthAndNothingElseIs) {
  sim::Scene scene =
      sim::loadScene(std::filesystem::path(GLASSMAP_SOURCE_DIR) / "maps" / GetParam().scene / "scene.yaml");
  sim::applySensorProfile(scene, sim::sensorProfile(GetParam().laser));
  scene.laser.rate = 10.0;  // as tools/sensor_sweep.py simulates it
  const LaserLog log = sim::simulate(scene).log;
  const MapResult r = mapLog(log);
  const glass::CellEvidence& e = r.evidence;
  const grid::GridGeometry& g = e.geometry;
  // Recall as cell F1@2 counts it: a cell on a pane's line (0.3 m from its ends) with a glass cell
  // within 2 cells; glass more than 3 cells from every pane is false.
  std::vector<Vec2> glass_cells;
  std::size_t on = 0, on_glass = 0, off_glass = 0;
  for (int y = 0; y < g.height; ++y) {
    for (int x = 0; x < g.width; ++x) {
      if (!isGlass(e.label[g.index(x, y)])) continue;
      glass_cells.push_back(g.center(x, y));
      if (paneDistance(scene.map, g.center(x, y), 0.0) > 3 * g.resolution) ++off_glass;
    }
  }
  for (int y = 0; y < g.height; ++y) {
    for (int x = 0; x < g.width; ++x) {
      const Vec2 p = g.center(x, y);
      if (paneDistance(scene.map, p, 0.3) > 0.5 * g.resolution) continue;
      ++on;
      for (const Vec2& q : glass_cells) {
        if ((q - p).norm() <= 2 * g.resolution + 1e-9) {
          ++on_glass;
          break;
        }
      }
    }
  }
  std::printf("%zu of %zu pane cells glass, %zu glass cells elsewhere\n", on_glass, on, off_glass);
  EXPECT_GE(on_glass, 0.7 * static_cast<double>(on));
  EXPECT_LE(static_cast<double>(off_glass), 0.1 * static_cast<double>(on));
}

// random:20: peak 0.52, lobe sigma 2.5 deg, 70% of the other beams reflected; its mirror images
// of the room drawn as glass all around it (cell F1@2 0.31) until the opaque-glass test took
// images seen only through other glass for what they are (glass/opaque_glass.hpp). In the glass
// corridor the walls and furniture of the rooms behind the panes passed for glass (F1@2 0.61):
// the straight continuations of the mirrored beams run past them, and those that slipped through
// one-cell gaps in a pane's labels counted as seen directly, until such a gap counted as the pane.
// random:27 (peak 0.42, sigma 2.6 deg, 10% at any angle, 2 cm noise) in the glass corridor, and
// random:4 (peak 0.61, sigma 4.5 deg, 8% at any angle, 2.7 cm noise + 1% of the range) in the
// glass room: with the default 2 deg / 0.9 lobe the classifier expected far more returns per pane
// cell than they give (F1@2 0.50 and 0.90 in tools/sensor_sweep.py), with the fitted lobe but
// without the range noise in the pane share (a noisy laser's returns spread over the cells about
// the pane) 0.53 and 0.69; with both 1.00 (pipeline/map_log.hpp, profile_lobe; applyProfile).
INSTANTIATE_TEST_SUITE_P(Lasers, FaintPanes,
                         ::testing::Values(Case{"random:7", "glass-room"}, Case{"random:20", "glass-room"},
                                           Case{"random:20", "glass-corridor"}, Case{"random:27", "glass-corridor"},
                                           Case{"random:4", "glass-room"}));

}  // namespace
}  // namespace glassmap::pipeline
