// Sensor profiles: every named profile's simulated outcome frequencies against its configured
// rates (glass response over incidence angle, spurious readings, range noise), random:SEED, names.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "glassmap/core/error.hpp"
#include "glassmap/geometry/optics.hpp"
#include "glassmap/geometry/ray_caster.hpp"
#include "glassmap/sim/sensor_profile.hpp"
#include "glassmap/sim/simulator.hpp"

using namespace glassmap;
using sim::BeamOutcome;
namespace fs = std::filesystem;

namespace {

double fraction(const sim::SimResult& r, BeamOutcome o) {
  std::size_t all = 0;
  for (std::size_t c : r.counts) all += c;
  return static_cast<double>(r.counts[static_cast<std::size_t>(o)]) / static_cast<double>(all);
}

// Binomial tolerance for a fraction p over n trials: 4.5 standard deviations plus a little.
double tolerance(double p, double n) { return 4.5 * std::sqrt(std::max(p * (1 - p), 1e-4) / n) + 0.003; }

double spurious(const sim::LaserSpec& l) { return l.dropout_rate + l.random_rate + l.short_rate; }

// A pane at x = 1 between the robot and a wall at x = 2, a wall behind at x = -1.5; the profile's
// laser cut to one beam straight ahead, driven for 1 s at 2 kHz from the origin at heading theta,
// so that the beam meets the pane at incidence theta. Max range 80 m so that every mirrored beam
// comes back: the glass response is what is measured here.
sim::Scene paneScene(const sim::SensorProfile& p, double theta_deg) {
  sim::Scene s;
  s.name = "pane";
  s.map.segments.push_back({Vec2(1, -50), Vec2(1, 50), Material::Glass, 0.08});
  s.map.segments.push_back({Vec2(2, -50), Vec2(2, 50), Material::Wall, 0.1});
  s.map.segments.push_back({Vec2(-1.5, -50), Vec2(-1.5, 50), Material::Wall, 0.1});
  sim::applySensorProfile(s, p);
  s.laser.fov = deg2rad(0.1);
  s.laser.resolution = deg2rad(1.0);
  s.laser.max_range = 80;
  s.laser.rate = 2000;
  s.motion = {};
  s.motion.slam_sigma_xy = 0;
  s.motion.slam_sigma_theta = 0;
  const double h = deg2rad(theta_deg);
  s.trajectory.waypoints = {Vec2(0, 0), Vec2(0.1 * std::cos(h), 0.1 * std::sin(h))};
  s.trajectory.speed = 0.1;
  s.trajectory.start_heading = std::nan("");
  return s;
}

// A closed 3 m x 3 m room around the origin, driven back and forth for `seconds` with the
// profile's laser as it is: every beam meets a wall within 2.4 m, inside every profile's range.
sim::Scene roomScene(const sim::SensorProfile& p) {
  sim::Scene s;
  s.name = "room";
  const Vec2 c[] = {{-1.5, -1.5}, {1.5, -1.5}, {1.5, 1.5}, {-1.5, 1.5}};
  for (int i = 0; i < 4; ++i) s.map.segments.push_back({c[i], c[(i + 1) % 4], Material::Wall, 0.1});
  sim::applySensorProfile(s, p);
  s.trajectory.waypoints = {Vec2(-0.3, 0), Vec2(0.3, 0)};
  s.trajectory.round_trip = true;
  s.trajectory.speed = 0.1;
  return s;
}

sim::SimOptions runFor(double seconds, std::uint64_t seed) {
  sim::SimOptions o;
  o.seed = seed;
  o.duration_limit = seconds;
  o.repeat_until_limit = true;
  return o;
}

}  // namespace

TEST(SensorProfile, NamedProfilesSpanTheGlassResponses) {
  const std::vector<std::string> names = sim::sensorProfileNames();
  ASSERT_EQ(names,
            (std::vector<std::string>{"sick-lms200", "hokuyo-urg04lx", "hokuyo-utm30lx", "rplidar-a2", "sick-tim571"}));
  // Beams per scan as the simulator counts them, against the datasheets.
  const std::size_t beams[] = {181, 683, 1081, 360, 811};
  const double max_range[] = {80, 4, 30, 12, 25};
  double sigma_lo = 1e9, sigma_hi = 0, peak_lo = 1e9, peak_hi = 0, floor_hi = 0, reflect_hi = 0;
  for (std::size_t i = 0; i < names.size(); ++i) {
    const sim::SensorProfile p = sim::sensorProfile(names[i]);
    EXPECT_EQ(p.name, names[i]);
    EXPECT_EQ(p.laser.model, names[i]);
    EXPECT_FALSE(p.description.empty());
    EXPECT_NO_THROW(sim::validateSensor(p.laser, p.glass));
    EXPECT_EQ(static_cast<std::size_t>(std::lround(p.laser.fov / p.laser.resolution)) + 1, beams[i]) << names[i];
    EXPECT_EQ(p.laser.max_range, max_range[i]) << names[i];
    EXPECT_GT(spurious(p.laser), 0.0) << names[i];
    EXPECT_EQ(p.glass.pane_thickness, 0.0);
    sigma_lo = std::min(sigma_lo, p.glass.direct_sigma_deg);
    sigma_hi = std::max(sigma_hi, p.glass.direct_sigma_deg);
    peak_lo = std::min(peak_lo, p.glass.direct_peak);
    peak_hi = std::max(peak_hi, p.glass.direct_peak);
    floor_hi = std::max(floor_hi, p.glass.direct_floor);
    reflect_hi = std::max(reflect_hi, p.glass.reflection_floor);
  }
  EXPECT_LE(sigma_lo, 1.0);
  EXPECT_GE(sigma_hi, 20.0);
  EXPECT_LE(peak_lo, 0.3);
  EXPECT_GE(peak_hi, 1.0);
  EXPECT_GE(floor_hi, 0.15);
  EXPECT_GE(reflect_hi, 0.3);  // phantoms far more frequent than Fresnel alone for some
}

TEST(SensorProfile, UnknownNamesThrow) {
  for (const char* bad : {"lidar-9000", "", "random:", "random:abc", "random:-1", "random:12x", "Random:1"}) {
    try {
      sim::sensorProfile(bad, "--sensor");
      ADD_FAILURE() << "expected an error for '" << bad << "'";
    } catch (const Error& e) {
      EXPECT_EQ(e.field(), "--sensor");
      EXPECT_NE(e.message().find("'" + std::string(bad) + "'"), std::string::npos) << e.what();
    }
  }
  try {
    sim::sensorProfile("lidar-9000");
  } catch (const Error& e) {
    EXPECT_NE(e.message().find("sick-tim571"), std::string::npos) << "lists the names: " << e.what();
  }
}

TEST(SensorProfile, RandomIsReproducibleAndInRange) {
  const sim::SensorProfile a = sim::sensorProfile("random:42"), b = sim::sensorProfile("random:42");
  EXPECT_EQ(a.name, "random:42");
  EXPECT_EQ(a.laser.model, "random:42");
  const auto numbers = [](const sim::SensorProfile& p) {
    const sim::LaserSpec& l = p.laser;
    const sim::GlassPhysics& g = p.glass;
    return std::vector<double>{l.fov,          l.resolution,      l.max_range,        l.rate,
                               l.range_sigma,  l.range_sigma_rel, l.dropout_rate,     l.random_rate,
                               l.short_rate,   l.short_lambda,    g.direct_peak,      g.direct_sigma_deg,
                               g.direct_floor, g.reflection_gain, g.reflection_floor, g.n_glass};
  };
  EXPECT_EQ(numbers(a), numbers(b));
  EXPECT_NE(numbers(a), numbers(sim::sensorProfile("random:43")));

  std::vector<double> fovs;
  double sigma_lo = 1e9, sigma_hi = 0;
  for (int seed = 0; seed < 300; ++seed) {
    const sim::SensorProfile p = sim::sensorProfile("random:" + std::to_string(seed));
    const sim::LaserSpec& l = p.laser;
    const sim::GlassPhysics& g = p.glass;
    EXPECT_NO_THROW(sim::validateSensor(l, g));
    // The geometry of one of the named profiles.
    bool named = false;
    for (const std::string& n : sim::sensorProfileNames()) {
      const sim::LaserSpec q = sim::sensorProfile(n).laser;
      named =
          named || (q.fov == l.fov && q.resolution == l.resolution && q.max_range == l.max_range && q.rate == l.rate);
    }
    EXPECT_TRUE(named) << p.name;
    fovs.push_back(l.fov);
    const auto in = [](double v, double lo, double hi) { return v >= lo && v <= hi; };
    EXPECT_TRUE(in(l.range_sigma, 0.003, 0.03) && in(l.range_sigma_rel, 0, 0.012)) << p.name;
    EXPECT_TRUE(in(l.dropout_rate, 0, 0.03) && in(l.random_rate, 0, 0.01) && in(l.short_rate, 0, 0.03)) << p.name;
    EXPECT_TRUE(in(l.short_lambda, 0.5, 3)) << p.name;
    EXPECT_TRUE(in(g.direct_peak, 0.3, 1) && in(g.direct_sigma_deg, 1, 20) && in(g.direct_floor, 0, 0.15)) << p.name;
    EXPECT_TRUE(in(g.reflection_gain, 0.5, 3) && in(g.reflection_floor, 0, 0.9) && in(g.n_glass, 1.47, 1.55)) << p.name;
    sigma_lo = std::min(sigma_lo, g.direct_sigma_deg);
    sigma_hi = std::max(sigma_hi, g.direct_sigma_deg);
  }
  // Drawn over the whole range, on more than one geometry.
  EXPECT_LT(sigma_lo, 2.0);
  EXPECT_GT(sigma_hi, 19.0);
  std::sort(fovs.begin(), fovs.end());
  EXPECT_GE(std::unique(fovs.begin(), fovs.end()) - fovs.begin(), 4);
}

// Per profile and incidence angle, the share of direct returns and of mirror phantoms on a single
// pane: (1 - spurious) P_direct(theta) and (1 - spurious) (1 - P_direct) P_reflect(theta), where
// P_direct = floor + (peak - floor) exp(-theta^2 / 2 sigma^2), P_reflect = max(floor, gain R).
TEST(SensorProfileSim, GlassResponseFollowsTheProfile) {
  for (const std::string& name : sim::sensorProfileNames()) {
    const sim::SensorProfile p = sim::sensorProfile(name);
    const sim::GlassPhysics& g = p.glass;
    const double keep = 1 - spurious(p.laser);
    for (const double theta_deg : {0.0, 2.0, 5.0, 10.0, 15.0, 20.0, 30.0, 45.0, 60.0}) {
      const sim::SimResult r = sim::simulate(paneScene(p, theta_deg), {17});
      const double n = static_cast<double>(r.log.scans.size());
      ASSERT_EQ(n, 2001);
      const double th = deg2rad(theta_deg), s = deg2rad(g.direct_sigma_deg);
      const double pd = g.direct_floor + (g.direct_peak - g.direct_floor) * std::exp(-th * th / (2 * s * s));
      const double pr =
          std::max(g.reflection_floor, std::min(1.0, g.reflection_gain * reflectance(th, 1.0, g.n_glass)));
      const double direct = keep * pd, reflected = keep * (1 - pd) * pr;
      EXPECT_NEAR(fraction(r, BeamOutcome::GlassDirect), direct, tolerance(direct, n)) << name << " " << theta_deg;
      EXPECT_NEAR(fraction(r, BeamOutcome::GlassReflected), reflected, tolerance(reflected, n))
          << name << " " << theta_deg;
      EXPECT_NEAR(fraction(r, BeamOutcome::GlassTransmitted), keep - direct - reflected,
                  tolerance(keep - direct - reflected, n))
          << name << " " << theta_deg;
    }
  }
}

TEST(SensorProfileSim, PaneThicknessOverridesTheMap) {
  sim::SensorProfile p = sim::sensorProfile("sick-lms200");
  p.laser.range_sigma = 0;
  p.laser.dropout_rate = p.laser.random_rate = p.laser.short_rate = 0;
  p.glass.direct_peak = p.glass.direct_floor = p.glass.reflection_gain = p.glass.reflection_floor = 0;
  p.glass.pane_thickness = 0.01;  // the map says 0.08
  const sim::SimResult r = sim::simulate(paneScene(p, 0.0), {3});
  const double elongation = paneRangeElongation(0.01, 0.0, p.glass.n_glass);
  for (std::size_t k = 0; k < r.log.scans.size(); ++k) {
    ASSERT_EQ(r.outcomes[k][0], BeamOutcome::GlassTransmitted);
    ASSERT_NEAR(r.log.scans[k].ranges[0], 2.0 - r.ground_truth[k].pose.x() + elongation, 1e-4);
  }
}

// Per profile in a closed room: the shares of dropouts, random and short readings are the
// configured rates; dropouts read max range, random readings are uniform in [0, max), short ones
// follow the truncated exponential; wall readings have the profile's range noise.
TEST(SensorProfileSim, SpuriousReadingsAndNoiseFollowTheProfile) {
  for (const std::string& name : sim::sensorProfileNames()) {
    const sim::SensorProfile p = sim::sensorProfile(name);
    const sim::LaserSpec& l = p.laser;
    const sim::Scene scene = roomScene(p);
    const sim::SimResult r = sim::simulate(scene, runFor(20.0, 5));
    const RayCaster caster(scene.map);
    double n = 0, random_sum = 0, random_n = 0, short_sum = 0, short_expected = 0, short_var = 0;
    double z_sum = 0, z_sq = 0, z_n = 0;
    for (std::size_t k = 0; k < r.log.scans.size(); ++k) {
      const LaserScan& scan = r.log.scans[k];
      const Pose2& pose = r.ground_truth[k].pose;
      for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
        ++n;
        const double z = scan.ranges[i];
        const double truth = caster.cast(pose.t, pose.theta + scan.beamAngle(i), l.max_range).range;
        switch (r.outcomes[k][i]) {
          case BeamOutcome::Dropout: ASSERT_EQ(z, static_cast<float>(l.max_range)); break;
          case BeamOutcome::Random:
            ASSERT_TRUE(z >= 0 && z <= l.max_range);
            random_sum += z / l.max_range;
            ++random_n;
            break;
          case BeamOutcome::Short: {
            ASSERT_TRUE(z >= 0 && z <= truth + 1e-4) << z << " " << truth;
            const double a = truth, lam = l.short_lambda;
            short_sum += z;
            short_expected += 1 / lam - a * std::exp(-lam * a) / (1 - std::exp(-lam * a));
            short_var += a * a / 6;  // generous: a truncated exponential varies less than a^2/12
            break;
          }
          case BeamOutcome::Wall: {
            const double sigma = std::hypot(l.range_sigma, l.range_sigma_rel * truth);
            const double e = (z - truth) / sigma;
            z_sum += e;
            z_sq += e * e;
            ++z_n;
            break;
          }
          default: ADD_FAILURE() << name << ": unexpected outcome " << sim::toString(r.outcomes[k][i]); return;
        }
      }
    }
    ASSERT_GT(n, 20000) << name;
    EXPECT_NEAR(fraction(r, BeamOutcome::Dropout), l.dropout_rate, tolerance(l.dropout_rate, n)) << name;
    EXPECT_NEAR(fraction(r, BeamOutcome::Random), l.random_rate, tolerance(l.random_rate, n)) << name;
    EXPECT_NEAR(fraction(r, BeamOutcome::Short), l.short_rate, tolerance(l.short_rate, n)) << name;
    ASSERT_GT(random_n, 50) << name;
    EXPECT_NEAR(random_sum / random_n, 0.5, 4.5 * std::sqrt(1.0 / 12 / random_n)) << name;
    EXPECT_NEAR(short_sum, short_expected, 4.5 * std::sqrt(short_var)) << name;
    // Standardised wall residuals: mean 0, standard deviation 1.
    const double mean = z_sum / z_n, sd = std::sqrt(z_sq / z_n - mean * mean);
    EXPECT_NEAR(mean, 0.0, 0.03) << name;
    EXPECT_NEAR(sd, 1.0, 0.03) << name;
  }
}

TEST(SensorProfileSim, SameSeedSameLog) {
  const sim::Scene scene = roomScene(sim::sensorProfile("random:9"));
  const sim::SimResult a = sim::simulate(scene, runFor(2.0, 4)), b = sim::simulate(scene, runFor(2.0, 4));
  const sim::SimResult c = sim::simulate(scene, runFor(2.0, 5));
  ASSERT_EQ(a.log.scans.size(), b.log.scans.size());
  bool equal = true, differ = false;
  for (std::size_t k = 0; k < a.log.scans.size(); ++k) {
    equal = equal && a.log.scans[k].ranges == b.log.scans[k].ranges && a.outcomes[k] == b.outcomes[k];
    differ = differ || a.log.scans[k].ranges != c.log.scans[k].ranges;
  }
  EXPECT_TRUE(equal);
  EXPECT_TRUE(differ);
}

TEST(Scene, SensorKeyPicksAProfileAndFieldsOverrideIt) {
  const fs::path dir = fs::temp_directory_path() / "glassmap_test_sensor_scene";
  fs::create_directories(dir);
  const std::string head =
      "floorplan: " + (fs::path(GLASSMAP_SOURCE_DIR) / "maps/no-glass/floorplan.geojson").string() +
      "\ntrajectory: {waypoints: [[1, 1], [2, 1]]}\n";
  const auto load = [&](const std::string& name, const std::string& body) {
    std::ofstream(dir / name) << head << body;
    return sim::loadScene(dir / name);
  };
  const sim::Scene plain = load("plain.yaml", "laser: {preset: sick-lms200}\n");
  EXPECT_TRUE(plain.sensor.empty());
  EXPECT_EQ(plain.laser.dropout_rate, 0.0);
  EXPECT_EQ(plain.glass.direct_floor, 0.0);

  const sim::Scene a = load("a.yaml", "sensor: rplidar-a2\nlaser: {rate: 5}\nglass: {direct_peak: 0.5}\n");
  const sim::SensorProfile rp = sim::sensorProfile("rplidar-a2");
  EXPECT_EQ(a.sensor, "rplidar-a2");
  EXPECT_EQ(a.laser.fov, rp.laser.fov);
  EXPECT_EQ(a.laser.range_sigma_rel, rp.laser.range_sigma_rel);
  EXPECT_EQ(a.laser.dropout_rate, rp.laser.dropout_rate);
  EXPECT_EQ(a.laser.rate, 5.0);         // the scene's field wins
  EXPECT_EQ(a.glass.direct_peak, 0.5);  // the scene's field wins
  EXPECT_EQ(a.glass.direct_sigma_deg, rp.glass.direct_sigma_deg);

  const sim::Scene b = load("b.yaml", "laser: {sensor: sick-tim571, dropout_rate: 0.1}\n");
  EXPECT_EQ(b.sensor, "sick-tim571");
  EXPECT_EQ(b.laser.dropout_rate, 0.1);
  EXPECT_EQ(b.glass.direct_floor, sim::sensorProfile("sick-tim571").glass.direct_floor);

  const std::pair<const char*, const char*> bad[] = {
      {"c.yaml", "sensor: lidar-9000\n"},
      {"d.yaml", "laser: {preset: sick-lms200, sensor: sick-tim571}\n"},
      {"e.yaml", "sensor: sick-lms200\nlaser: {sensor: sick-tim571}\n"},
      {"f.yaml", "sensor: sick-lms200\nlaser: {dropout_rate: 0.7, random_rate: 0.4}\n"},
      {"g.yaml", "glass: {direct_peak: 0.1, direct_floor: 0.2}\n"},
  };
  for (const auto& [file, body] : bad) {
    try {
      load(file, body);
      ADD_FAILURE() << "expected an error for " << body;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
    }
  }
  try {
    load("c.yaml", "sensor: lidar-9000\n");
  } catch (const Error& e) {
    EXPECT_NE(e.message().find("lidar-9000"), std::string::npos) << e.what();
    EXPECT_EQ(e.line(), 3u);
  }
  fs::remove_all(dir);
}
