// The pipeline module: one call maps a log through every step, one call localizes a log; the
// steps can be switched off; the files written read back as the result.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "glassmap/core/error.hpp"
#include "glassmap/core/labels.hpp"
#include "glassmap/core/scan_spool.hpp"
#include "glassmap/eval/cells.hpp"
#include "glassmap/eval/trajectory.hpp"
#include "glassmap/io/labels_raster.hpp"
#include "glassmap/io/ros_map.hpp"
#include "glassmap/io/sensor_profile.hpp"
#include "glassmap/pipeline/localize_log.hpp"
#include "glassmap/pipeline/map_files.hpp"
#include "glassmap/pipeline/map_log.hpp"
#include "glassmap/sim/simulator.hpp"
#include "glassmap/vector/from_evidence.hpp"

namespace glassmap::pipeline {
namespace {

namespace fs = std::filesystem;

// The first 40 s of paper-corridor (seed 1): several panes seen, a few seconds to map.
struct Scene {
  sim::Scene scene;
  sim::SimResult run;
};
const Scene& corridor() {
  static const Scene s = [] {
    Scene x;
    x.scene = sim::loadScene(fs::path(GLASSMAP_SOURCE_DIR) / "maps" / "paper-corridor" / "scene.yaml");
    sim::SimOptions so;
    so.seed = 1;
    so.duration_limit = 40.0;
    x.run = sim::simulate(x.scene, so);
    return x;
  }();
  return s;
}

const MapResult& defaultMap() {
  static const MapResult r = mapLog(corridor().run.log);
  return r;
}

TEST(Pipeline, MethodNamesRoundTrip) {
  for (MapMethod m : {MapMethod::Heuristic, MapMethod::Direct, MapMethod::Mrf})
    EXPECT_EQ(parseMapMethod(toString(m)), m);
  EXPECT_THROW(parseMapMethod("graphcut"), Error);
}

TEST(Pipeline, DefaultsRunEveryStepAndFindTheGlass) {
  const MapResult& r = defaultMap();
  EXPECT_GT(r.mrf.active_cells, 0u);
  EXPECT_GT(r.phantoms.beams_through_glass, 0u);
  EXPECT_GT(r.opaque.glass_cells, 0u);
  ASSERT_TRUE(r.has_floorplan);
  EXPECT_GT(r.floorplan.map.count(Material::Glass), 0u);
  EXPECT_GT(r.floorplan.map.count(Material::Wall), 0u);
  // Counts are of the final labels.
  EXPECT_EQ(r.stats.glass_cells, r.evidence.countGlass());
  EXPECT_EQ(r.stats.occupied_cells, r.evidence.countOccupied());
  EXPECT_GE(r.seconds.total, r.seconds.mrf + r.seconds.vectorize);
  // Glass cells found are real glass (the run saw only part of the corridor: recall is partial).
  const eval::CellEvalResult c =
      eval::evaluateCells(corridor().scene.map, r.evidence.geometry, r.evidence.label, r.evidence.bins);
  EXPECT_GE(c.tolerant.precision, 0.95);
  EXPECT_GT(c.found, 50u);
  std::printf("40 s of paper-corridor: %zu glass cells found, %zu false, P@2 %.3f R@2 %.3f\n", c.found,
              c.false_positives, c.tolerant.precision, c.tolerant.recall);
}

TEST(Pipeline, IsTheChainOfItsStagesInOrder) {
  // The same steps called one by one give the same labels and the same floorplan.
  // (The default run calibrates: its last pass used the thresholds of the fitted profile.)
  const LaserLog& log = corridor().run.log;
  const MapResult& r = defaultMap();
  ASSERT_TRUE(r.calibrated);
  MapOptions defaults;
  applyProfile(defaults, r.profile);
  glass::MappingResult m = glass::mapLog(log, defaults.mapping);
  mrf::refine(m.evidence, defaults.mrf);
  if (defaults.sparse_panes) glass::findSparsePanes(log, defaults.mapping.beams, defaults.sparse, m.evidence);
  glass::relabelOpaqueGlass(log, defaults.mapping.beams, defaults.opaque, m.evidence);
  glass::suppressMirrorPhantoms(log, defaults.mapping.beams, defaults.phantom, m.evidence);
  vector::VectorizeResult v = vector::vectorize(vector::toLabelGrid(m.evidence), defaults.vectorize);
  vector::fitToScans(v, log, defaults.mapping.beams, defaults.scan_fit);
  const std::size_t pruned = vector::pruneUnfittedGlass(m.evidence, v.map, defaults.prune_tolerance);
  const std::size_t filled = vector::fillFittedGlass(m.evidence, v.map);
  EXPECT_EQ(r.evidence.label, m.evidence.label);
  EXPECT_EQ(r.pruned_glass, pruned);
  EXPECT_EQ(r.filled_glass, filled);
  ASSERT_EQ(r.floorplan.map.segments.size(), v.map.segments.size());
  for (std::size_t i = 0; i < v.map.segments.size(); ++i) {
    EXPECT_EQ(r.floorplan.map.segments[i].a, v.map.segments[i].a);
    EXPECT_EQ(r.floorplan.map.segments[i].b, v.map.segments[i].b);
  }
}

TEST(Pipeline, StepsCanBeSwitchedOff) {
  const LaserLog& log = corridor().run.log;
  MapOptions o;
  o.method = MapMethod::Direct;
  o.phantoms = false;
  o.opaque_glass = false;
  o.sparse_panes = false;
  o.fit_floorplan = false;
  o.prune_unfitted_glass = false;
  const MapResult bare = mapLog(log, o);
  EXPECT_EQ(bare.mrf.active_cells, 0u);
  EXPECT_EQ(bare.phantoms.beams_through_glass, 0u);
  EXPECT_EQ(bare.opaque.glass_cells, 0u);
  EXPECT_EQ(bare.sparse.weak_returns, 0u);
  EXPECT_FALSE(bare.has_floorplan);
  EXPECT_TRUE(bare.floorplan.map.segments.empty());
  EXPECT_EQ(bare.pruned_glass, 0u);
  // The pane fit needs the floorplan: it is fitted even when no floorplan is asked for.
  o.prune_unfitted_glass = true;
  const MapResult pruned = mapLog(log, o);
  EXPECT_TRUE(pruned.has_floorplan);
  EXPECT_LE(pruned.stats.glass_cells, bare.stats.glass_cells + pruned.filled_glass);
  // The heuristic is another classifier: it labels differently.
  o.method = MapMethod::Heuristic;
  const MapResult heuristic = mapLog(log, o);
  EXPECT_NE(heuristic.evidence.label, pruned.evidence.label);
}

// A noisier laser with a wider, weaker glass lobe than the defaults assume.
const Scene& noisyCorridor() {
  static const Scene s = [] {
    Scene x;
    x.scene = sim::loadScene(fs::path(GLASSMAP_SOURCE_DIR) / "maps" / "paper-corridor" / "scene.yaml");
    x.scene.laser.range_sigma = 0.03;
    x.scene.glass.direct_sigma_deg = 4.0;
    x.scene.glass.direct_peak = 0.55;
    sim::SimOptions so;
    so.seed = 1;
    so.duration_limit = 60.0;
    x.run = sim::simulate(x.scene, so);
    return x;
  }();
  return s;
}

// The classifiers no longer lean on the 2 deg lobe (no-return handling, pane voting, a pane
// smoothness that charges nothing across the pane): the calibrated map must not be worse than the
// default one, and the profile must be the laser's.
TEST(Pipeline, CalibratesToTheLaserAndMapsNoWorseForIt) {
  const Scene& s = noisyCorridor();
  MapOptions with_lobe;
  with_lobe.profile_lobe = true;
  const MapResult calibrated = mapLog(s.run.log, with_lobe);
  ASSERT_TRUE(calibrated.calibrated);
  const SensorProfile& p = calibrated.profile;
  EXPECT_NEAR(p.range_sigma_m.value, 0.03, 0.25 * 0.03);
  EXPECT_NEAR(p.direct_sigma_deg.value, 4.0, 0.25 * 4.0);
  EXPECT_NEAR(p.direct_peak.value, 0.55, 0.1);
  MapOptions fixed;
  fixed.calibrate = false;
  const MapResult uncalibrated = mapLog(s.run.log, fixed);
  EXPECT_FALSE(uncalibrated.calibrated);
  auto f1 = [&](const MapResult& r) {
    return eval::evaluateCells(s.scene.map, r.evidence.geometry, r.evidence.label, r.evidence.bins).tolerant.f1;
  };
  const double with = f1(calibrated), without = f1(uncalibrated);
  std::printf("noisy laser, 60 s of paper-corridor: glass cell F1@2 %.3f calibrated, %.3f with the defaults\n", with,
              without);
  EXPECT_GT(with, 0.8);
  // Within 0.02: in these 60 s the calibrated lobe (the laser's own 4 deg) takes for glass a 0.7 m
  // mirror image of a wall across a pane that neither map finds, which the 2 deg default does not
  // (0.855 / 0.865 before the cells were filled along the fitted panes, 0.852 / 0.869 after).
  EXPECT_GE(with, without - 0.02);
  // The 4 deg lobe is not the first pass's 2 deg: a second pass maps with it.
  EXPECT_GE(calibrated.passes, 2);
  // A given profile is used as is, in one pass.
  MapOptions given = with_lobe;
  given.sensor = p;
  const MapResult reused = mapLog(s.run.log, given);
  EXPECT_FALSE(reused.calibrated);
  EXPECT_EQ(reused.evidence.label, calibrated.evidence.label);
}

TEST(Pipeline, ApplyProfileKeepsWhatTheCallerSet) {
  SensorProfile p;
  p.range_sigma_m.value = 0.08;
  p.direct_sigma_deg.value = 9.0;
  p.direct_floor.value = 0.1;
  MapOptions o;
  o.mapping.direct.direct_peak = 0.42;  // set by the caller
  MapOptions noise_only = o;
  noise_only.profile_lobe = false;
  applyProfile(noise_only, p);
  EXPECT_DOUBLE_EQ(noise_only.mapping.direct.direct_sigma_deg, MapOptions{}.mapping.direct.direct_sigma_deg);
  EXPECT_NEAR(noise_only.mapping.beams.miss_margin, 0.24, 1e-12);
  applyProfile(o, p);  // the lobe follows the profile by default
  EXPECT_DOUBLE_EQ(o.mapping.direct.direct_peak, 0.42);
  EXPECT_DOUBLE_EQ(o.mapping.direct.direct_sigma_deg, 9.0);
  EXPECT_DOUBLE_EQ(o.mapping.direct.direct_floor, 0.1);
  EXPECT_NEAR(o.mapping.beams.miss_margin, 0.24, 1e-12);
  EXPECT_NEAR(o.vectorize.noise_floor, 0.08 / o.mapping.resolution, 1e-12);
  EXPECT_NEAR(o.scan_fit.band, 0.16, 1e-12);   // 2 sigma
  EXPECT_NEAR(o.scan_fit.reach, 0.31, 1e-12);  // the band and the 0.15 m a precise laser's walls may move
  // A precise laser keeps the defaults' margins.
  MapOptions precise;
  SensorProfile q;
  q.range_sigma_m.value = 0.005;
  applyProfile(precise, q);
  EXPECT_DOUBLE_EQ(precise.mapping.beams.miss_margin, MapOptions{}.mapping.beams.miss_margin);
  EXPECT_DOUBLE_EQ(precise.vectorize.noise_floor, MapOptions{}.vectorize.noise_floor);
  EXPECT_DOUBLE_EQ(precise.scan_fit.band, MapOptions{}.scan_fit.band);
  EXPECT_DOUBLE_EQ(precise.scan_fit.reach, MapOptions{}.scan_fit.reach);
}

// Simulated 20 deg lobes fit 20.1-21.2 deg with standard errors of 0.1 deg: a lobe as wide as
// glass shows is kept on every log, not only where its fit happens to read low; fits far wider
// (Freiburg 079's door frames: 26.2 +- 2.7 deg) and faint ones give way to the prior.
TEST(Pipeline, ALobeAsWideAsGlassShowsIsKeptWhateverItsFitReads) {
  const MapOptions o;
  const SensorProfile prior;
  const auto kept = [&](double sigma, double se, double peak = 0.89, double peak_se = 0.002) {
    sensor::CalibrationResult fit;
    fit.profile.direct_sigma_deg = {sigma, se, true};
    fit.profile.direct_peak = {peak, peak_se, true};
    fit.profile.direct_floor = {0.15, 0.002, true};
    const bool keep = keepPlausibleLobe(o, prior, fit);
    EXPECT_EQ(fit.warnings.empty(), keep) << sigma;
    EXPECT_DOUBLE_EQ(fit.profile.direct_sigma_deg.value, keep ? sigma : prior.direct_sigma_deg.value) << sigma;
    EXPECT_DOUBLE_EQ(fit.profile.direct_floor.value, keep ? 0.15 : prior.direct_floor.value) << sigma;
    return keep;
  };
  for (const double sigma : {2.0, 12.3, 19.4, 20.0, 20.2, 21.2, 21.9}) EXPECT_TRUE(kept(sigma, 0.1)) << sigma;
  EXPECT_TRUE(kept(23.0, 2.0));        // not wider than 20 deg beyond its errors
  EXPECT_FALSE(kept(22.5, 0.1));       // beyond the errors and the fit's bias
  EXPECT_FALSE(kept(26.2, 2.7));       // Freiburg 079's
  EXPECT_FALSE(kept(8.0, 0.5, 0.01));  // too faint for glass
  // A peak within two standard errors of none (Freiburg 079's first pass at stop 42: 0.105 +- 0.091,
  // 0.87 +- 0.53 deg, which mapped the log twice more for nothing), and one just outside them.
  EXPECT_FALSE(kept(0.87, 0.53, 0.105, 0.091));
  EXPECT_TRUE(kept(1.0, 0.2, 0.19, 0.09));
  sensor::CalibrationResult none;  // no lobe fitted: nothing to judge
  EXPECT_TRUE(keepPlausibleLobe(o, prior, none));
  EXPECT_TRUE(none.warnings.empty());
}

TEST(Pipeline, MapFilesReadBackAsTheResult) {
  const MapResult& r = defaultMap();
  const fs::path dir = fs::temp_directory_path() / ("glassmap_pipeline_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const auto written = writeMapFiles(dir, r);
  for (const char* name :
       {"map.yaml", "map.pgm", "labels.tif", "map.png", "sensor.yaml", "floorplan.gpkg", "floorplan.dxf"})
    EXPECT_TRUE(fs::exists(dir / name)) << name;
  EXPECT_EQ(written.size(), 5u + 5u);
  EXPECT_DOUBLE_EQ(readSensorProfile(dir / "sensor.yaml").direct_sigma_deg.value, r.profile.direct_sigma_deg.value);
  const LabelRaster raster = readLabelRaster(dir / "labels.tif");
  EXPECT_EQ(raster.codes, toLabelRaster(r.evidence).codes);
  const OccupancyGridMap ros = readRosMap(dir / "map.yaml");
  ASSERT_EQ(ros.data.size(), r.evidence.label.size());
  for (std::size_t i = 0; i < ros.data.size(); ++i) {
    const int l = r.evidence.label[i];
    const int expected = l == kUnknown ? -1 : l == kEmpty ? 0 : 100;  // glass is an obstacle there
    ASSERT_EQ(ros.data[i], expected) << "cell " << i;
  }
  fs::remove_all(dir);
  // Without floorplan files only the grid products are written.
  const auto grid_only = writeMapFiles(dir, r, false);
  EXPECT_EQ(grid_only.size(), 5u);
  EXPECT_FALSE(fs::exists(dir / "floorplan.gpkg"));
  fs::remove_all(dir);
}

// Cells whose labels differ between two maps of one grid. The same log moved far away is shifted
// back to a local frame, but its coordinates keep the rounding of the far ones (about 1e-10 m), and
// a decision that lies that close to its threshold may go the other way: once the classifier took
// the fitted lobe, one beam of this log folded in the mirror-phantom test at the origin and not at
// the far offsets (3013 against 3012 folded beams), and one cell of about 250,000 changed. Why that
// beam lies so close to the threshold was not traced.
std::size_t labelsDiffering(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
  if (a.size() != b.size()) return std::max(a.size(), b.size());
  std::size_t n = 0;
  for (std::size_t i = 0; i < a.size(); ++i) n += a[i] != b[i];
  return n;
}

TEST(Pipeline, ResultsDoNotDependOnWhereTheFrameOriginLies) {
  // The same log in UTM-like coordinates (and farther) maps to the same cells and segments.
  const MapResult& near = defaultMap();
  for (const Vec2& offset : {Vec2(500000.0, 5400000.0), Vec2(257000.0, 9857000.0), Vec2(-3e7, 2e7)}) {
    LaserLog far = corridor().run.log;
    for (LaserScan& s : far.scans) s.laser_pose.t += offset;
    const MapResult r = mapLog(far);
    EXPECT_LE(labelsDiffering(r.evidence.label, near.evidence.label), 2u) << offset.transpose();
    EXPECT_LT((r.evidence.geometry.origin - offset - near.evidence.geometry.origin).norm(), 1e-6);
    ASSERT_EQ(r.floorplan.map.segments.size(), near.floorplan.map.segments.size()) << offset.transpose();
    for (std::size_t i = 0; i < near.floorplan.map.segments.size(); ++i) {
      EXPECT_LT((r.floorplan.map.segments[i].a - offset - near.floorplan.map.segments[i].a).norm(), 1e-3)
          << offset.transpose() << " segment " << i;
      EXPECT_LT((r.floorplan.map.segments[i].b - offset - near.floorplan.map.segments[i].b).norm(), 1e-3);
    }
  }
}

TEST(Pipeline, ALogKeptOnDiskMapsToTheSameResult) {
  // A log too large for memory is spooled and every pass reads it back in blocks: the same
  // labels, profile and floorplan as the log in memory, also when the frame is re-centred.
  const fs::path dir = fs::temp_directory_path() / ("glassmap-pipeline-spool-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  for (const Vec2& offset : {Vec2(0.0, 0.0), Vec2(500000.0, 5400000.0)}) {
    auto spool = std::make_shared<ScanSpool>(dir);
    for (LaserScan s : corridor().run.log.scans) {
      s.laser_pose.t += offset;
      spool->append(s);
    }
    spool->flush();
    LaserLog disk;
    disk.spooled = SpooledScans{spool, Vec2::Zero(), {}, 1u << 18};  // about 30 blocks
    const MapResult r = mapLog(disk);
    const MapResult& near = defaultMap();
    if (offset.isZero())
      EXPECT_EQ(r.evidence.label, near.evidence.label);  // the same numbers: the same labels
    else
      EXPECT_LE(labelsDiffering(r.evidence.label, near.evidence.label), 2u) << offset.transpose();
    EXPECT_EQ(r.profile.range_sigma_m.value, near.profile.range_sigma_m.value);
    EXPECT_EQ(r.stats.beams, near.stats.beams);
    ASSERT_EQ(r.floorplan.map.segments.size(), near.floorplan.map.segments.size());
    for (std::size_t i = 0; i < near.floorplan.map.segments.size(); ++i)
      EXPECT_LT((r.floorplan.map.segments[i].a - offset - near.floorplan.map.segments[i].a).norm(), 1e-3);
  }
  EXPECT_TRUE(fs::is_empty(dir));
  fs::remove_all(dir);
}

TEST(Pipeline, LocalizesALogAgainstTheFloorplan) {
  const Scene& s = corridor();
  LocalizeOptions o;
  o.filter.filter.max_particles = 300;
  o.filter.init = s.run.ground_truth.front().pose;
  const LocalizeResult r = localizeLog(s.run.log, s.scene.map, o);
  EXPECT_EQ(r.model, "glass");
  ASSERT_EQ(r.run.trajectory.size(), s.run.log.scans.size());
  const eval::TrajectoryErrors e = eval::evaluateTrajectory(s.run.ground_truth, r.run.trajectory);
  EXPECT_LT(e.rmse, 0.05);
  // Started at the true pose, the cloud is one tight mode throughout.
  EXPECT_TRUE(r.run.converged);
  EXPECT_DOUBLE_EQ(r.run.converged_at, 0.0);
  EXPECT_EQ(std::count(r.run.settled.begin(), r.run.settled.end(), 1), static_cast<long>(r.run.settled.size()));
  EXPECT_THROW(localizeLog(s.run.log, VectorMap{}, o), Error);
  o.model = "telepathy";
  EXPECT_THROW(localizeLog(s.run.log, s.scene.map, o), Error);
}

TEST(Pipeline, LocalizesTheSameWhereverThePlanLies) {
  // The plan and the start in UTM-like coordinates: the same estimates, moved (the filter works
  // in a frame re-centred on the plan; the log's odometry only moves the particles).
  const Scene& s = corridor();
  LocalizeOptions o;  // the command line's defaults
  o.filter.init = s.run.ground_truth.front().pose;
  const LocalizeResult near = localizeLog(s.run.log, s.scene.map, o);
  const Vec2 offset(500000.0, 5400000.0);
  VectorMap far = s.scene.map;
  for (MapSegment& seg : far.segments) seg.a += offset, seg.b += offset;
  o.filter.init->t += offset;
  const LocalizeResult r = localizeLog(s.run.log, far, o);
  ASSERT_EQ(r.run.trajectory.size(), near.run.trajectory.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < r.run.trajectory.size(); ++i)
    worst = std::max(worst, (r.run.trajectory[i].pose.t - offset - near.run.trajectory[i].pose.t).norm());
  EXPECT_LT(worst, 1e-6);
}

TEST(Pipeline, GlobalLocalizationSaysWhetherItConverged) {
  const sim::Scene scene = sim::loadScene(fs::path(GLASSMAP_SOURCE_DIR) / "maps" / "glass-corridor" / "scene.yaml");
  LocalizeOptions o;
  o.filter.filter.max_particles = 2000;  // no initial pose: global localization
  // 4 s of a symmetric glass corridor: the cloud cannot settle, and the run says so.
  sim::SimOptions brief;
  brief.seed = 3;
  brief.duration_limit = 4.0;
  const sim::SimResult short_run = sim::simulate(scene, brief);
  const LocalizeResult unsure = localizeLog(short_run.log, scene.map, o);
  EXPECT_FALSE(unsure.run.converged);
  EXPECT_LT(unsure.run.converged_at, 0.0);
  EXPECT_EQ(std::count(unsure.run.settled.begin(), unsure.run.settled.end(), 1), 0);
  // The whole run: converged, and every pose flagged as converged is right.
  sim::SimOptions whole;
  whole.seed = 1;
  const sim::SimResult run = sim::simulate(scene, whole);
  const LocalizeResult sure = localizeLog(run.log, scene.map, o);
  ASSERT_TRUE(sure.run.converged);
  EXPECT_GT(sure.run.converged_at, 0.0);
  const eval::TrajectoryErrors e = eval::evaluateTrajectory(run.ground_truth, sure.run.trajectory);
  std::size_t flagged = 0;
  for (std::size_t k = 0; k < sure.run.trajectory.size(); ++k) {
    if (!sure.run.settled[k]) continue;
    ++flagged;
    const double t = sure.run.trajectory[k].timestamp;
    const auto it = std::find(e.times.begin(), e.times.end(), t);
    ASSERT_NE(it, e.times.end());
    EXPECT_LT(e.position_errors[static_cast<std::size_t>(it - e.times.begin())], 0.2) << "t " << t;
  }
  EXPECT_GT(flagged, sure.run.trajectory.size() / 2);
}

}  // namespace
}  // namespace glassmap::pipeline
