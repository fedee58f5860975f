// Sensor models: every model is a density over range (property test over all of them), the glass
// modes' geometry, the paper variant's negative region and its guard, the distance grid.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "glassmap/core/error.hpp"
#include "glassmap/sensor/beam_model.hpp"
#include "glassmap/sensor/field_model.hpp"
#include "glassmap/sensor/glass_model.hpp"
#include "glassmap/sensor/sensor_model.hpp"
#include "sensor_test_maps.hpp"

namespace glassmap::sensor {
namespace {

using test::seg;

// A 10 x 12 m room around the origin with a 2 m glass pane centred at (3, 0) whose normal makes
// `theta_deg` with the x axis (the beam along +x meets it at that incidence).
VectorMap roomWithPane(double theta_deg) {
  VectorMap m;
  m.segments.push_back(seg({-2, -6}, {8, -6}));
  m.segments.push_back(seg({8, -6}, {8, 6}));
  m.segments.push_back(seg({8, 6}, {-2, 6}));
  m.segments.push_back(seg({-2, 6}, {-2, -6}));
  const double a = deg2rad(theta_deg);
  const Vec2 along(-std::sin(a), std::cos(a));
  m.segments.push_back(seg(Vec2(3, 0) - along, Vec2(3, 0) + along, Material::Glass, 0.01));
  return m;
}

VectorMap loneWall() {
  VectorMap m;
  m.segments.push_back(seg({4, -20}, {4, 20}));
  return m;
}

// Integral over [0, z_max) of p(z) plus the max-reading mass, for a beam along `angle` from `pose`.
double integrate(const SensorModel& model, const Pose2& pose, double angle, double z_max) {
  const double dz = 0.0005;
  double sum = 0.0;
  for (double z = 0.5 * dz; z < z_max; z += dz) sum += std::exp(model.beamLogLikelihood(pose, angle, z, z_max)) * dz;
  return sum + std::exp(model.beamLogLikelihood(pose, angle, z_max, z_max));
}

struct Case {
  const char* what;
  VectorMap map;
  double angle;
  bool field_valid;  // the field model integrates to 1 only at normal incidence on a lone surface
};

std::vector<Case> cases() {
  return {{"lone wall, normal incidence", loneWall(), 0.0, true}, {"nothing within range", loneWall(), kPi, false},
          {"wall at 40 deg", loneWall(), deg2rad(40.0), false},   {"pane at 0 deg", roomWithPane(0.0), 0.0, false},
          {"pane at 1.5 deg", roomWithPane(1.5), 0.0, false},     {"pane at 30 deg", roomWithPane(30.0), 0.0, false},
          {"pane at 75 deg", roomWithPane(75.0), 0.0, false},     {"pane at 85 deg", roomWithPane(85.0), 0.0, false}};
}

// Property test over every model and both glass treatments: p(z) integrates to 1 over range.
TEST(SensorModels, EveryModelIntegratesToOneOverRange) {
  const double z_max = 12.0;
  for (const std::string& name : sensorModelNames()) {
    if (name == "glass-paper") continue;  // not a density: see PaperVariantIsNotADensity
    for (GlassAs glass_as : {GlassAs::Opaque, GlassAs::Invisible}) {
      SensorParams p;
      p.max_range = z_max;
      p.glass_as = glass_as;
      for (const Case& c : cases()) {
        if (name == "field" && !c.field_valid) continue;
        const auto model = makeSensorModel(name, c.map, p);
        EXPECT_NEAR(integrate(*model, Pose2(), c.angle, z_max), 1.0, 0.01)
            << name << " (glass " << toString(glass_as) << "): " << c.what;
      }
    }
  }
}

TEST(SensorModels, FieldModelOverweightsObliqueSurfacesByOneOverCos) {
  SensorParams p;
  p.max_range = 12.0;
  const auto model = makeSensorModel("field", loneWall(), p);
  const double theta = deg2rad(40.0);
  // Weights normalised over hit, max and random (no short term): 0.85, 0.05, 0.05 over 0.95.
  const double hit_mass = integrate(*model, Pose2(), theta, 12.0) - 0.1 / 0.95;
  EXPECT_NEAR(hit_mass, (0.85 / 0.95) / std::cos(theta), 0.02);
  // And it has no notion of an expected range: with nothing in range the hit mass is lost.
  EXPECT_NEAR(integrate(*model, Pose2(), kPi, 12.0), 0.1 / 0.95, 0.01);
}

TEST(SensorModels, PaperVariantIsNotADensity) {
  // Modes a few cm wide are densities above 1: the paper's sum minus products overshoots where
  // two modes overlap and undershoots elsewhere; its integral is not 1.
  SensorParams p;
  p.max_range = 12.0;
  const auto model = makeSensorModel("glass-paper", roomWithPane(0.0), p);
  const double integral = integrate(*model, Pose2(), 0.0, 12.0);
  EXPECT_GT(std::abs(integral - 1.0), 0.05) << integral;
}

// The batch call (beam-major in the field model) gives every pose exactly what one call gives,
// for every model, with max readings among the beams and a scan whose max range is not the one
// the model was built for (the field model's table is then bypassed).
TEST(SensorModels, BatchLikelihoodsEqualOneCallPerPose) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Pose2> poses;
  for (int j = 0; j < 150; ++j) poses.emplace_back(0.5 * u(rng), 0.5 * u(rng), kPi * u(rng));
  for (const std::string& name : sensorModelNames()) {
    SensorParams p;
    p.max_range = 12.0;
    const auto model = makeSensorModel(name, roomWithPane(30.0), p);
    for (double max_range : {12.0, 10.0}) {
      LaserScan scan;
      scan.max_range = max_range;
      scan.start_angle = -kPi / 2;
      scan.angular_step = kPi / 40;
      for (int i = 0; i <= 40; ++i) scan.ranges.push_back(i % 7 == 3 ? static_cast<float>(max_range) : 1.0f + 0.1f * i);
      const BeamSet beams = makeBeamSet(scan, 0);
      std::vector<double> batch(poses.size());
      model->logLikelihoods(poses, beams, batch.data());
      for (std::size_t j = 0; j < poses.size(); ++j)
        ASSERT_EQ(batch[j], model->logLikelihood(poses[j], beams)) << name << " pose " << j << " max " << max_range;
    }
  }
}

TEST(SensorModels, FactoryNamesAndErrors) {
  const VectorMap m = loneWall();
  for (const std::string& name : sensorModelNames()) EXPECT_EQ(makeSensorModel(name, m)->name(), name);
  EXPECT_THROW(makeSensorModel("laser", m), Error);
  EXPECT_EQ(parseGlassAs("Invisible"), GlassAs::Invisible);
  EXPECT_THROW(parseGlassAs("clear"), Error);
  SensorParams bad;
  bad.sigma_hit = 0;
  EXPECT_THROW(makeSensorModel("beam", m, bad), Error);
}

TEST(BeamModel, PeaksAtTheExpectedRangeAndSeesGlassAsConfigured) {
  SensorParams p;
  const VectorMap m = roomWithPane(0.0);  // pane at 3 m, wall at 8 m behind it
  const auto opaque = makeSensorModel("beam", m, p);
  p.glass_as = GlassAs::Invisible;
  const auto invisible = makeSensorModel("beam", m, p);
  const Pose2 x;
  EXPECT_GT(opaque->beamLogLikelihood(x, 0, 3.0, 30), opaque->beamLogLikelihood(x, 0, 3.1, 30));
  EXPECT_GT(opaque->beamLogLikelihood(x, 0, 3.0, 30), opaque->beamLogLikelihood(x, 0, 8.0, 30) + 5);
  EXPECT_GT(invisible->beamLogLikelihood(x, 0, 8.0, 30), invisible->beamLogLikelihood(x, 0, 3.0, 30) + 5);
  // Short readings are likelier than long unexpected ones (people in front of the wall).
  EXPECT_GT(opaque->beamLogLikelihood(x, 0, 1.0, 30), opaque->beamLogLikelihood(x, 0, 20.0, 30));
  // A max reading is likely only when nothing is within range.
  const auto lone = makeSensorModel("beam", loneWall(), p);
  EXPECT_NEAR(lone->beamLogLikelihood(x, kPi, 30, 30), std::log(0.85 + 0.05), 1e-12);
  EXPECT_NEAR(lone->beamLogLikelihood(x, 0.0, 30, 30), std::log(0.05), 1e-12);
}

TEST(GlassModel, ModesFollowThePaperGeometry) {
  SensorParams p;
  p.offset = 0.05;
  GlassModel model(roomWithPane(30.0), p);
  const RayCaster caster(model.map());
  const Vec2 dir(1, 0);
  const RayHit hit = caster.cast(Vec2::Zero(), dir, 30.0);
  ASSERT_EQ(hit.material, Material::Glass);
  const GlassModes m = model.modes(Vec2::Zero(), dir, hit, 30.0);
  EXPECT_NEAR(m.d_g, 3.0, 1e-9);
  EXPECT_NEAR(m.theta_deg, 30.0, 1e-9);
  EXPECT_NEAR(m.w_direct, std::exp(-900.0 / 6.0), 1e-12);
  EXPECT_NEAR(m.w_normal, std::exp(-0.09 * 60.0), 1e-12);
  EXPECT_NEAR(m.w_refract, 1.0 - m.w_direct - m.w_normal, 1e-12);
  EXPECT_NEAR(m.e_refract, 8.0 + 0.05, 1e-9);  // d_real to the wall at x = 8 plus the offset
  // Mirrored at a pane whose normal is at 30 deg, the ray leaves (3, 0) at -120 deg and meets the
  // wall y = -6 after 6 / sin(60 deg).
  EXPECT_NEAR(m.e_normal, 3.0 + 6.0 / std::sin(deg2rad(60.0)), 1e-9);
}

TEST(GlassModel, ExplainsEachModeWhereTheBeamModelCannot) {
  SensorParams p;
  const Pose2 x;
  // Near normal incidence the pane echoes: a reading at d_g is likely.
  const auto g0 = makeSensorModel("glass", roomWithPane(0.0), p);
  EXPECT_GT(g0->beamLogLikelihood(x, 0, 3.0, 30), 1.0);
  // At 30 deg the beam goes through: d_real is likely, d_g is not.
  const auto g30 = makeSensorModel("glass", roomWithPane(30.0), p);
  EXPECT_GT(g30->beamLogLikelihood(x, 0, 8.0, 30), 1.0);
  EXPECT_LT(g30->beamLogLikelihood(x, 0, 3.0, 30), -1.0);
  const auto beam30 = makeSensorModel("beam", roomWithPane(30.0), p);
  EXPECT_LT(beam30->beamLogLikelihood(x, 0, 8.0, 30), -3.0);
  // At 85 deg the mirrored path dominates.
  GlassModel g85(roomWithPane(85.0), p);
  const RayHit hit = RayCaster(g85.map()).cast(Vec2::Zero(), Vec2(1, 0), 30.0);
  const GlassModes m = g85.modes(Vec2::Zero(), Vec2(1, 0), hit, 30.0);
  EXPECT_GT(m.w_normal, m.w_refract);
  EXPECT_GT(g85.beamLogLikelihood(x, 0, m.e_normal, 30), 1.0);
}

TEST(GlassModel, PaperVariantGoesNegativeWhereModesOverlapAndTheLogIsGuarded) {
  // A pane along y = 0 and walls at y = +-1.5: from (0, 1) at 80 deg incidence the mirrored and the
  // continued ray travel equally far, so the refraction and normal-reflection modes coincide.
  VectorMap m;
  m.segments.push_back(seg({-40, 0}, {40, 0}, Material::Glass, 0.01));
  m.segments.push_back(seg({-40, 1.5}, {40, 1.5}));
  m.segments.push_back(seg({-40, -1.5}, {40, -1.5}));
  SensorParams p;
  p.offset = 0.0;
  GlassModel paper(m, p, GlassModel::Variant::Paper), mixture(m, p, GlassModel::Variant::Mixture);
  const Pose2 x(0, 1, 0);
  const double angle = -deg2rad(10.0);  // 80 deg from the pane normal (the y axis)
  const Vec2 dir(std::cos(angle), std::sin(angle));
  const RayHit hit = RayCaster(m).cast(x.t, dir, 30.0);
  ASSERT_EQ(hit.material, Material::Glass);
  const GlassModes modes = paper.modes(x.t, dir, hit, 30.0);
  ASSERT_NEAR(modes.e_normal, modes.e_refract, 1e-9);
  const double z = modes.e_normal;
  const double s = 0.05, g = 1.0 / (std::sqrt(2 * kPi) * s);
  const double a1 = modes.w_refract * g, a2 = modes.w_normal * g;
  ASSERT_LT(a1 + a2 - a1 * a2, 0.0);  // the paper's formula is negative here
  const double floor = std::log(0.05 / 30.0);
  EXPECT_NEAR(paper.beamLogLikelihood(x, angle, z, 30), floor, 1e-9);
  EXPECT_TRUE(std::isfinite(paper.beamLogLikelihood(x, angle, z, 30)));
  EXPECT_GT(mixture.beamLogLikelihood(x, angle, z, 30), 1.0);
}

TEST(DistanceGrid, MatchesExactDistancesWithinOneCell) {
  const VectorMap m = roomWithPane(20.0);
  const DistanceGrid grid(m, true, 0.025, 1.0);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> ux(-3, 9), uy(-7, 7);
  for (int i = 0; i < 2000; ++i) {
    const Vec2 q(ux(rng), uy(rng));
    EXPECT_NEAR(grid.distance(q), grid.exactDistance(q), 0.025) << q.transpose();
  }
  EXPECT_DOUBLE_EQ(grid.distance({100, 100}), 1.0);
  const DistanceGrid walls_only(m, false, 0.025, 1.0);
  EXPECT_NEAR(walls_only.distance({3, 0}), 1.0, 1e-6);  // the pane is not there
}

TEST(BeamSet, SubsamplesEvenlyIncludingBothEnds) {
  LaserScan scan;
  scan.start_angle = -deg2rad(135);
  scan.angular_step = deg2rad(0.25);
  scan.max_range = 30;
  scan.ranges.assign(1081, 5.0f);
  scan.ranges[540] = kNoReturn;
  const BeamSet all = makeBeamSet(scan, 0);
  EXPECT_EQ(all.size(), 1081u);
  EXPECT_DOUBLE_EQ(all.ranges[540], 30.0);
  const BeamSet k = makeBeamSet(scan, 5);
  ASSERT_EQ(k.size(), 5u);
  EXPECT_NEAR(k.angles.front(), -deg2rad(135), 1e-12);
  EXPECT_NEAR(k.angles.back(), deg2rad(135), 1e-12);
  EXPECT_NEAR(k.angles[2], 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(k.ranges[2], 30.0);  // the no-return beam became a max reading
  EXPECT_NEAR((k.points[0] - 5.0 * k.dirs[0]).norm(), 0.0, 1e-12);
}

}  // namespace
}  // namespace glassmap::sensor
