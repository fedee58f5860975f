// Self-calibration against simulated lasers whose parameters are known.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <random>

#include "glassmap/core/angles.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/geometry/ray_caster.hpp"
#include "glassmap/sensor/calibrate.hpp"
#include "glassmap/sensor/glass_model.hpp"
#include "glassmap/sim/scene.hpp"
#include "glassmap/sim/simulator.hpp"

namespace glassmap {
namespace {

namespace fs = std::filesystem;
constexpr double kInf = std::numeric_limits<double>::infinity();

sim::Scene corridor(double range_sigma, double lobe_sigma_deg, double peak) {
  sim::Scene scene = sim::loadScene(fs::path(GLASSMAP_SOURCE_DIR) / "maps" / "glass-corridor" / "scene.yaml");
  scene.laser.range_sigma = range_sigma;
  scene.glass.direct_sigma_deg = lobe_sigma_deg;
  scene.glass.direct_peak = peak;
  return scene;
}

LaserLog simulateFor(const sim::Scene& scene, double seconds) {
  sim::SimOptions o;
  o.seed = 3;
  o.duration_limit = seconds;
  return sim::simulate(scene, o).log;
}

struct Case {
  double range_sigma, lobe_sigma, peak;
};

class CalibrateLaser : public ::testing::TestWithParam<Case> {};

TEST_P(CalibrateLaser, RecoversNoiseAndLobeAgainstTheTruePlan) {
  const Case c = GetParam();
  const sim::Scene scene = corridor(c.range_sigma, c.lobe_sigma, c.peak);
  const LaserLog log = simulateFor(scene, 40.0);
  const sensor::CalibrationResult r = sensor::calibrate(log, scene.map);
  const SensorProfile& p = r.profile;
  ASSERT_TRUE(p.range_sigma_m.fitted);
  ASSERT_TRUE(p.direct_sigma_deg.fitted);
  EXPECT_NEAR(p.range_sigma_m.value, c.range_sigma, 0.10 * c.range_sigma);
  EXPECT_NEAR(r.range_sigma_local_m, c.range_sigma, 0.15 * c.range_sigma);
  EXPECT_NEAR(p.direct_sigma_deg.value, c.lobe_sigma, 0.15 * c.lobe_sigma);
  EXPECT_NEAR(p.direct_peak.value, c.peak, 0.06);
  EXPECT_LT(p.direct_floor.value, 0.02);
  // The standard errors are honest: the truth lies within a few of them (or they are tiny).
  EXPECT_LT(std::abs(p.direct_sigma_deg.value - c.lobe_sigma), 6 * p.direct_sigma_deg.se + 0.05 * c.lobe_sigma);
  EXPECT_GT(p.w_hit.value, 0.9);
  EXPECT_EQ(r.aligned_scans, r.scans);
}

INSTANTIATE_TEST_SUITE_P(Lasers, CalibrateLaser,
                         ::testing::Values(Case{0.01, 2.0, 0.9}, Case{0.03, 4.0, 0.55}, Case{0.02, 10.0, 0.7}));

TEST(Calibrate, AlignmentKeepsPoseErrorOutOfTheRangeNoise) {
  const sim::Scene scene = corridor(0.01, 2.0, 0.9);
  LaserLog log = simulateFor(scene, 30.0);
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n(0.0, 1.0);
  for (LaserScan& s : log.scans)
    s.laser_pose = Pose2(s.laser_pose.t + 0.03 * Vec2(n(rng), n(rng)), s.laser_pose.theta + deg2rad(0.5) * n(rng));
  sensor::CalibrationOptions aligned, raw;
  raw.align_scans = false;
  const sensor::CalibrationResult a = sensor::calibrate(log, scene.map, aligned);
  const sensor::CalibrationResult b = sensor::calibrate(log, scene.map, raw);
  EXPECT_NEAR(a.profile.range_sigma_m.value, 0.01, 0.002);
  EXPECT_GT(b.profile.range_sigma_m.value, 0.02);  // pose error passes for range noise
  EXPECT_GT(a.median_alignment_m, 0.02);
  // The in-scan estimate never sees the poses.
  EXPECT_NEAR(b.range_sigma_local_m, 0.01, 0.0015);
}

// A triangulation-like laser whose noise grows with range: both the wall fit and the in-scan fit
// see the growth, and a laser with constant noise is not given any.
TEST(Calibrate, NoiseThatGrowsWithRange) {
  sim::Scene scene = corridor(0.004, 2.0, 0.9);
  scene.laser.range_sigma_rel = 0.008;
  const LaserLog log = simulateFor(scene, 40.0);
  for (const sensor::SigmaSource source : {sensor::SigmaSource::Walls, sensor::SigmaSource::Local}) {
    sensor::CalibrationOptions o;
    o.sigma_source = source;
    const SensorProfile p = sensor::calibrate(log, scene.map, o).profile;
    ASSERT_TRUE(p.range_sigma_rel.fitted) << static_cast<int>(source);
    EXPECT_NEAR(p.range_sigma_rel.value, 0.008, 0.0025) << static_cast<int>(source);
    EXPECT_NEAR(rangeSigmaAt(p, 4.0), std::hypot(0.004, 0.032), 0.006) << static_cast<int>(source);
    EXPECT_GT(p.typical_range_m, 0.5);
  }
  const sim::Scene flat = corridor(0.01, 2.0, 0.9);
  const SensorProfile q = sensor::calibrate(simulateFor(flat, 40.0), flat.map).profile;
  EXPECT_NEAR(rangeSigmaAt(q, 5.0), 0.01, 0.002);
}

// A wide lobe with a floor (a SICK TiM-like laser): many neighbouring readings straddle a pane and
// the wall seen through it. The in-scan estimate takes them for outliers, not for noise (their
// median absolute deviation put sigma 30% high).
TEST(Calibrate, InScanNoiseIsNotInflatedByReadingsThatStraddleAPane) {
  sim::Scene scene = corridor(0.02, 20.0, 0.9);
  scene.glass.direct_floor = 0.15;
  const LaserLog log = simulateFor(scene, 40.0);
  sensor::CalibrationOptions o;
  o.sigma_source = sensor::SigmaSource::Local;
  const sensor::CalibrationResult r = sensor::calibrate(log, scene.map, o);
  EXPECT_NEAR(r.profile.range_sigma_m.value, 0.02, 0.002);
  EXPECT_NEAR(rangeSigmaAt(r.profile, r.profile.typical_range_m), 0.02, 0.002);
}

TEST(Calibrate, WithoutGlassKeepsTheGlassPriorAndSaysSo) {
  sim::Scene scene = corridor(0.02, 2.0, 0.9);
  VectorMap walls;
  for (const MapSegment& s : scene.map.segments)
    if (s.material == Material::Wall) walls.segments.push_back(s);
  scene.map = walls;
  const LaserLog log = simulateFor(scene, 20.0);
  sensor::CalibrationOptions o;
  o.prior.direct_sigma_deg.value = 7.0;
  const sensor::CalibrationResult r = sensor::calibrate(log, scene.map, o);
  EXPECT_TRUE(r.profile.range_sigma_m.fitted);
  EXPECT_FALSE(r.profile.direct_sigma_deg.fitted);
  EXPECT_DOUBLE_EQ(r.profile.direct_sigma_deg.value, 7.0);
  EXPECT_EQ(r.profile.glass_beams, 0u);
  EXPECT_FALSE(r.warnings.empty());
}

TEST(Calibrate, RefusesAnEmptyLogAndAPlanWithoutWalls) {
  const sim::Scene scene = corridor(0.01, 2.0, 0.9);
  EXPECT_THROW(sensor::calibrate(LaserLog{}, scene.map), Error);
  VectorMap glass_only;
  for (const MapSegment& s : scene.map.segments)
    if (s.material == Material::Glass) glass_only.segments.push_back(s);
  EXPECT_THROW(sensor::calibrate(simulateFor(scene, 2.0), glass_only), Error);
}

// A plan with a 3 m "pane" 2 m before a wall, and a log of a laser driving past it. `answers`
// decides whether scan k's beam at incidence theta [deg] comes back from the pane; a beam that does
// not ends on the wall.
template <class Answers>
LaserLog paneLog(const VectorMap& plan, Answers answers) {
  const RayCaster caster(plan);
  std::mt19937_64 rng(11);
  std::normal_distribution<double> noise(0.0, 0.01);
  LaserLog log;
  for (int k = 0; k < 600; ++k) {
    LaserScan scan;
    scan.timestamp = 0.1 * k;
    scan.start_angle = -deg2rad(90.0);
    scan.angular_step = deg2rad(0.25);
    scan.max_range = 20.0;
    scan.laser_pose = Pose2(Vec2(0.0, -1.0 + 2.0 * k / 600.0), 0.0);
    for (int i = 0; i <= 720; ++i) {
      const Vec2 d(std::cos(scan.beamAngle(static_cast<std::size_t>(i))),
                   std::sin(scan.beamAngle(static_cast<std::size_t>(i))));
      RayHit hit = caster.cast(scan.laser_pose.t, d, scan.max_range);
      double range = hit.range;
      if (hit.hit() && hit.material == Material::Glass && !answers(k, rad2deg(hit.incidence), rng)) {
        const RayHit behind = caster.cast(scan.laser_pose.t + hit.range * d, d, scan.max_range, hit.segment);
        range = behind.hit() ? hit.range + behind.range : kInf;
      }
      scan.ranges.push_back(std::isfinite(range) ? static_cast<float>(range + noise(rng)) : kNoReturn);
    }
    log.scans.push_back(std::move(scan));
  }
  return log;
}

// People walking by, drawn as glass by a first pass, answer every beam while there and none
// before or after: their "pane" is left out of the glass fit, where it would fit a lobe to people.
// A real pane's beams answer one by one at its lobe's rate: it stays in, and its lobe is fitted.
TEST(Calibrate, PanesThatAnswerScanByScanArePeopleNotGlass) {
  VectorMap plan;
  plan.segments.push_back({Vec2(4.0, -12.0), Vec2(4.0, 12.0), Material::Wall});
  plan.segments.push_back({Vec2(2.0, -1.5), Vec2(2.0, 1.5), Material::Glass});
  SensorProfile lobe;
  lobe.direct_peak.value = 0.8;
  lobe.direct_sigma_deg.value = 5.0;
  const LaserLog pane = paneLog(plan, [&](int, double theta, std::mt19937_64& rng) {
    return std::bernoulli_distribution(directProbability(lobe, theta))(rng);
  });
  // Someone stands in front of the "pane" now and then: 5 visits of 3 s.
  const LaserLog people = paneLog(plan, [](int k, double, std::mt19937_64&) { return k % 120 < 30; });

  const sensor::CalibrationResult glass = sensor::calibrate(pane, plan);
  EXPECT_EQ(glass.transient_panes, 0u);
  ASSERT_TRUE(glass.profile.direct_sigma_deg.fitted);
  EXPECT_NEAR(glass.profile.direct_sigma_deg.value, 5.0, 0.75);

  const sensor::CalibrationResult passers_by = sensor::calibrate(people, plan);
  EXPECT_EQ(passers_by.transient_panes, 1u);
  EXPECT_NEAR(passers_by.transient_length_m, 3.0, 1e-9);
  EXPECT_FALSE(passers_by.profile.direct_sigma_deg.fitted);
  EXPECT_TRUE(std::any_of(passers_by.warnings.begin(), passers_by.warnings.end(),
                          [](const std::string& w) { return w.find("people") != std::string::npos; }));
  // Without the test the people fit a lobe: a wide one, at every angle.
  sensor::CalibrationOptions keep_all;
  keep_all.max_transient_p = 0.0;
  const sensor::CalibrationResult fooled = sensor::calibrate(people, plan, keep_all);
  EXPECT_EQ(fooled.transient_panes, 0u);
  EXPECT_TRUE(fooled.profile.direct_sigma_deg.fitted);
}

// The in-scan noise needs no plan, and calibrate's Local source gives the very same numbers (the
// map pipeline maps a log once when its lobe keeps the prior's: its first pass has the noise).
TEST(Calibrate, InScanNoiseBeforeAnyPlanIsWhatTheLocalFitGives) {
  sim::Scene scene = corridor(0.004, 2.0, 0.9);
  scene.laser.range_sigma_rel = 0.008;
  const LaserLog log = simulateFor(scene, 20.0);
  SensorProfile before;
  ASSERT_TRUE(sensor::inScanNoise(log, {}, before));
  EXPECT_TRUE(before.range_sigma_m.fitted);
  EXPECT_NEAR(rangeSigmaAt(before, 4.0), std::hypot(0.004, 0.032), 0.006);
  sensor::CalibrationOptions local;
  local.sigma_source = sensor::SigmaSource::Local;
  const SensorProfile after = sensor::calibrate(log, scene.map, local).profile;
  EXPECT_EQ(before.range_sigma_m.value, after.range_sigma_m.value);
  EXPECT_EQ(before.range_sigma_rel.value, after.range_sigma_rel.value);
  EXPECT_EQ(before.typical_range_m, after.typical_range_m);
  EXPECT_GT(before.typical_range_m, 0.5);
  // The Prior source takes that estimate as it is instead of making it again: the same profile,
  // the same in-scan figure.
  sensor::CalibrationOptions again = local;
  again.prior = before;  // as the map pipeline fits: from the profile its first pass used
  const sensor::CalibrationResult made_again = sensor::calibrate(log, scene.map, again);
  sensor::CalibrationOptions given;
  given.sigma_source = sensor::SigmaSource::Prior;
  given.prior = before;
  const sensor::CalibrationResult taken = sensor::calibrate(log, scene.map, given);
  EXPECT_EQ(taken.profile.range_sigma_m.value, made_again.profile.range_sigma_m.value);
  EXPECT_EQ(taken.profile.range_sigma_m.se, made_again.profile.range_sigma_m.se);
  EXPECT_EQ(taken.profile.range_sigma_rel.value, made_again.profile.range_sigma_rel.value);
  EXPECT_EQ(taken.profile.typical_range_m, made_again.profile.typical_range_m);
  EXPECT_EQ(taken.range_sigma_local_m, made_again.range_sigma_local_m);
  EXPECT_EQ(taken.profile.direct_sigma_deg.value, made_again.profile.direct_sigma_deg.value);
  EXPECT_EQ(taken.profile.w_hit.value, made_again.profile.w_hit.value);
  // Too few readings: nothing estimated, the profile untouched.
  SensorProfile none;
  EXPECT_FALSE(sensor::inScanNoise(LaserLog{}, {}, none));
  EXPECT_FALSE(none.range_sigma_m.fitted);
}

TEST(Calibrate, ProfileCurvesFollowTheirParameters) {
  SensorProfile p;
  p.direct_peak.value = 0.8;
  p.direct_sigma_deg.value = 5.0;
  p.direct_floor.value = 0.1;
  EXPECT_NEAR(directProbability(p, 0.0), 0.8, 1e-12);
  EXPECT_NEAR(directProbability(p, 5.0), 0.1 + 0.7 * std::exp(-0.5), 1e-12);
  EXPECT_NEAR(directProbability(p, 80.0), 0.1, 1e-9);
  p.normal_floor.value = 0.2;
  p.normal_lambda_per_deg.value = 0.05;
  EXPECT_NEAR(reflectedProbability(p, 90.0), 1.0, 1e-12);
  EXPECT_NEAR(reflectedProbability(p, 70.0), 0.2 + 0.8 * std::exp(-1.0), 1e-12);
}

}  // namespace
}  // namespace glassmap

namespace glassmap {
namespace {

// A laser whose noise grows with range is taken beam by beam: sigma(z) = hypot(sigma_0, rel z),
// sigma_0 floored; the beam model's density of a reading 4 cm short of its wall is that Gaussian's
// (far: wide, near: sharp), not one sigma's for every beam.
TEST(ProfileParams, RangeNoiseGrowsWithTheReading) {
  SensorProfile p;
  p.range_sigma_m.value = 0.005;
  p.range_sigma_rel.value = 0.01;
  const sensor::SensorParams floored = sensor::paramsFromProfile(p);
  EXPECT_DOUBLE_EQ(floored.sigma_hit, 0.02);
  EXPECT_DOUBLE_EQ(floored.sigma_hit_rel, 0.01);
  const sensor::SensorParams params = sensor::paramsFromProfile(p, {}, 0.001);
  EXPECT_DOUBLE_EQ(params.sigma_hit, 0.005);
  EXPECT_NEAR(sensor::sigmaAt(params, 5.0), std::hypot(0.005, 0.05), 1e-15);
  sensor::SensorParams only_hits = params;
  only_hits.z_short = only_hits.z_max = 0.0;
  only_hits.z_rand = 1e-9;
  for (const double wall : {1.0, 8.0}) {
    VectorMap one;
    one.add({wall, -20}, {wall, 20}, Material::Wall);
    const auto m = sensor::makeSensorModel("beam", one, only_hits);
    const double z = wall - 0.04, sigma = std::hypot(0.005, 0.01 * z);
    const double expected = -0.5 * std::pow(0.04 / sigma, 2) - std::log(std::sqrt(2.0 * kPi) * sigma);
    EXPECT_NEAR(m->logLikelihood(Pose2(), Vec2(1, 0), z, 30.0), expected, 1e-6) << wall;
    sensor::SensorParams flat = only_hits;
    flat.sigma_hit_rel = 0.0;
    const auto f = sensor::makeSensorModel("beam", one, flat);
    const double with_growth = m->logLikelihood(Pose2(), Vec2(1, 0), z, 30.0);
    const double without = f->logLikelihood(Pose2(), Vec2(1, 0), z, 30.0);
    if (wall > 5.0) {
      EXPECT_GT(with_growth, without + 10.0);  // 4 cm is 0.5 sigma at 8 m, 8 sigma at 0 m
    }
  }
}

TEST(ProfileParams, TheGlassModelTakesTheProfilesLobeAndFloors) {
  VectorMap map;
  map.add({2, -5}, {2, 5}, Material::Glass);
  map.add({6, -5}, {6, 5}, Material::Wall);
  SensorProfile p;
  p.range_sigma_m.value = 0.005;
  p.direct_peak.value = 0.5;
  p.direct_sigma_deg.value = 10.0;
  p.direct_floor.value = 0.1;
  p.normal_lambda_per_deg.value = 0.01;
  p.normal_floor.value = 0.3;
  const sensor::SensorParams params = sensor::paramsFromProfile(p);
  EXPECT_DOUBLE_EQ(params.sigma_hit, 0.02);  // floored: the map is not that precise
  EXPECT_DOUBLE_EQ(sensor::paramsFromProfile(p, {}, 0.001).sigma_hit, 0.005);
  const sensor::GlassModel model(map, params);
  const RayCaster caster(map);
  for (double theta_deg : {0.0, 10.0, 60.0}) {
    const Vec2 dir(std::cos(deg2rad(theta_deg)), std::sin(deg2rad(theta_deg)));
    const RayHit hit = caster.cast(Vec2::Zero(), dir, 30.0);
    ASSERT_EQ(hit.material, Material::Glass);
    const sensor::GlassModes m = model.modes(Vec2::Zero(), dir, hit, 30.0);
    EXPECT_NEAR(m.w_direct, directProbability(p, theta_deg), 1e-9) << theta_deg;
    EXPECT_NEAR(m.w_normal, reflectedProbability(p, theta_deg), 1e-9) << theta_deg;
  }
  // The defaults are the paper's lobe, bit for bit.
  const sensor::SensorParams paper;
  EXPECT_EQ(paper.direct_peak, 1.0);
  EXPECT_EQ(paper.direct_floor, 0.0);
  EXPECT_EQ(paper.normal_floor, 0.0);
}

}  // namespace
}  // namespace glassmap
