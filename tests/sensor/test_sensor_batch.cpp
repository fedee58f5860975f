// The models' batch calls (castGroups, SIMD mixture lanes) against the per-beam reference: the sum
// over beams of logLikelihood(pose, dir, z, max_range), which casts one ray at a time and takes the
// scalar Mixture. Equal up to float rounding, on a scene with several panes in a row (transmitted
// rays through more than one pane), particle clouds and scattered poses, max readings and readings
// short of, at and beyond the surfaces.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "glassmap/core/angles.hpp"
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
  for (const std::string& name : sensorModelNames()) {
    SensorParams p;
    p.max_range = 15.0;
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
      ASSERT_NEAR(batch[j], reference, 1e-9 * std::abs(reference)) << name << " pose " << j;
      ASSERT_EQ(batch[j], model->logLikelihood(poses[j], beams)) << name << " pose " << j;  // one-pose call
    }
  }
}

}  // namespace
}  // namespace glassmap::sensor
