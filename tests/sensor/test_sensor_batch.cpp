// The models' batch calls (castGroups, SIMD mixture lanes) against the per-beam reference: the sum
// over beams of logLikelihood(pose, dir, z, max_range), which casts one ray at a time and takes the
// scalar Mixture. Equal up to float rounding, on a scene with several panes in a row (transmitted
// rays through more than one pane), particle clouds and scattered poses, max readings and readings
// short of, at and beyond the surfaces.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "glassmap/core/angles.hpp"
#include "glassmap/geometry/ray_caster.hpp"
#include "glassmap/sensor/glass_model.hpp"
#include "glassmap/sensor/sensor_model.hpp"
#include "sensor_test_maps.hpp"

namespace glassmap::sensor {
namespace {

using test::seg;

// A 20 x 12 m room with a row of three panes across it (0.01 m thick, tilted a little) and a
// glass-fronted box in a corner.
VectorMap panesRoom() {
  VectorMap m;
  m.segments.push_back(seg({-10, -6}, {10, -6}));
  m.segments.push_back(seg({10, -6}, {10, 6}));
  m.segments.push_back(seg({10, 6}, {-10, 6}));
  m.segments.push_back(seg({-10, 6}, {-10, -6}));
  for (double x : {2.0, 4.0, 6.0}) m.segments.push_back(seg({x, -4}, {x + 0.3, 4}, Material::Glass, 0.01));
  m.segments.push_back(seg({-9, 3}, {-6, 3}, Material::Glass, 0.008));
  m.segments.push_back(seg({-6, 3}, {-6, 5.5}));
  return m;
}

TEST(SensorBatch, BatchEqualsPerBeamReferenceUpToRounding) {
  std::mt19937 rng(41);
  std::normal_distribution<double> n01(0.0, 1.0);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const VectorMap map = panesRoom();
  std::vector<Pose2> poses;
  for (int j = 0; j < 300; ++j)  // a cloud (what the filter weighs) ...
    poses.emplace_back(-2 + 0.1 * n01(rng), 0.5 + 0.1 * n01(rng), 0.05 * n01(rng));
  for (int j = 0; j < 100; ++j)  // ... and poses anywhere in the room
    poses.emplace_back(9 * u(rng), 5 * u(rng), kPi * u(rng));
  for (const std::string& name : sensorModelNames())
    for (const double rel : {0.0, 0.01}) {  // one sigma, and sigma growing with the reading
      SensorParams p;
      p.max_range = 15.0;
      p.sigma_hit_rel = rel;
      const auto model = makeSensorModel(name, map, p);
      LaserScan scan;
      scan.max_range = 15.0;
      scan.start_angle = -0.75 * kPi;
      scan.angular_step = 1.5 * kPi / 180;
      for (int i = 0; i <= 180; ++i) {
        const double r = i % 11 == 5 ? 15.0 : 0.2 + 14.0 * (0.5 + 0.5 * u(rng));  // max readings too
        scan.ranges.push_back(static_cast<float>(r));
      }
      const BeamSet beams = makeBeamSet(scan, 61);
      std::vector<double> batch(poses.size());
      model->logLikelihoods(poses, beams, batch.data());
      for (std::size_t j = 0; j < poses.size(); ++j) {
        double reference = 0.0;
        const Eigen::Matrix2d R = poses[j].rotation();
        for (std::size_t i = 0; i < beams.size(); ++i)
          reference += model->logLikelihood(poses[j], Vec2(R * beams.dirs[i]), beams.ranges[i], beams.max_range);
        ASSERT_NEAR(batch[j], reference, 1e-9 * std::abs(reference)) << name << " rel " << rel << " pose " << j;
        ASSERT_EQ(batch[j], model->logLikelihood(poses[j], beams)) << name << " pose " << j;  // one-pose call
      }
    }
}

// Beam by beam, the batch call's log-likelihood of a pane hit (weights and mode densities on SIMD
// lanes with libmvec's atan, exp and expm1, each within 4 ulp) against the one-ray path (libm's):
// readings at and around each of the three modes (where their densities and hence any error in
// them weigh most) and anywhere. The bound: libmvec's 4 ulp on the incidence and the exponentials
// stay within 1e-12 of the log of each beam's probability.
TEST(SensorBatch, PaneHitsOnLanesWithinRoundingOfTheOneRayPathPerBeam) {
  std::mt19937 rng(43);
  std::normal_distribution<double> n01(0.0, 1.0);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const VectorMap map = panesRoom();
  const RayCaster caster(map);
  SensorParams p;
  p.max_range = 15.0;
  p.sigma_hit_rel = 0.005;  // each beam's densities with the sigma of its reading
  std::vector<Pose2> poses;
  for (int j = 0; j < 60; ++j) poses.emplace_back(-2 + 0.1 * n01(rng), 0.5 + 0.1 * n01(rng), 0.05 * n01(rng));
  for (int j = 0; j < 60; ++j) poses.emplace_back(9 * u(rng), 5 * u(rng), kPi * u(rng));
  for (const auto variant : {GlassModel::Variant::Mixture, GlassModel::Variant::Paper}) {
    const GlassModel model(map, p, variant);
    double worst = 0.0;
    int pane_beams = 0;
    for (const Pose2& pose : poses) {
      for (int i = 0; i < 61; ++i) {
        const double a = pose.theta + (-0.75 + 1.5 * i / 60.0) * kPi;
        const Vec2 dir(std::cos(a), std::sin(a));
        const RayHit hit = caster.cast(pose.t, dir, p.max_range);
        if (!hit.hit() || hit.material != Material::Glass) continue;
        ++pane_beams;
        const GlassModes m = model.modes(pose.t, dir, hit, p.max_range);
        for (const double e : {m.d_g, m.e_normal, m.e_refract, 0.2 + 14.0 * (0.5 + 0.5 * u(rng))}) {
          if (!std::isfinite(e)) continue;
          const double z = std::clamp(e + 0.03 * n01(rng), 0.01, 14.99);
          BeamSet one;
          one.max_range = p.max_range;
          one.angles.push_back(a - pose.theta);
          one.dirs.emplace_back(std::cos(a - pose.theta), std::sin(a - pose.theta));
          one.ranges.push_back(z);
          one.points.push_back(z * one.dirs.back());
          const double batch = model.logLikelihood(pose, one);
          const double reference = model.logLikelihood(pose, Vec2(pose.rotation() * one.dirs[0]), z, p.max_range);
          ASSERT_TRUE(std::isfinite(batch) && std::isfinite(reference));
          worst = std::max(worst, std::abs(batch - reference));
        }
      }
    }
    EXPECT_GT(pane_beams, 500);
    EXPECT_LE(worst, 1e-12) << model.name();
    std::printf("%s: largest |batch - one-ray| log-likelihood of a pane beam %.3g over %d beams\n",
                model.name().c_str(), worst, pane_beams);
  }
}

}  // namespace
}  // namespace glassmap::sensor
