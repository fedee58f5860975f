#include "glassmap/sim/sensor_profile.hpp"

#include <charconv>
#include <cmath>

#include "glassmap/core/error.hpp"
#include "glassmap/core/split_mix.hpp"

namespace glassmap::sim {
namespace {

struct Geometry {
  double fov_deg, resolution_deg, max_range, rate;
};

struct Noise {
  double sigma, sigma_rel, dropout, random, short_rate, short_lambda;
};

struct Response {
  double peak, sigma_deg, floor, gain, reflection_floor, n_glass;
};

struct Named {
  const char* name;
  const char* description;
  Geometry geometry;
  Noise noise;
  Response glass;
};

// The numbers and their sources: maps/README.md, "Sensor profiles". The URG-04LX has 1024 steps
// per turn and reads steps 44..725 (683 beams); the RPLIDAR spins a full turn (360 beams).
constexpr double kUrgStep = 360.0 / 1024.0;
const Named kProfiles[] = {
    {"sick-lms200",
     "SICK LMS200: 180 deg / 1 deg / 80 m, 905 nm pulsed; narrow bright-echo lobe",
     {180.0, 1.0, 80.0, 37.5},
     {0.01, 0.0, 0.002, 0.001, 0.005, 1.0},
     {0.95, 3.0, 0.0, 1.0, 0.10, 1.5}},
    {"hokuyo-urg04lx",
     "Hokuyo URG-04LX: 240 deg / 0.35 deg / 4 m, 785 nm phase shift; mixed pixels, dropouts",
     {682 * kUrgStep, kUrgStep, 4.0, 10.0},
     {0.01, 0.005, 0.02, 0.005, 0.03, 2.0},
     {0.6, 6.0, 0.02, 1.0, 0.30, 1.5}},
    {"hokuyo-utm30lx",
     "Hokuyo UTM-30LX: 270 deg / 0.25 deg / 30 m, 905 nm pulsed; wide glass response as measured",
     {270.0, 0.25, 30.0, 40.0},
     {0.01, 0.00045, 0.005, 0.002, 0.01, 1.0},
     {1.0, 15.0, 0.10, 1.0, 0.50, 1.5}},
    {"rplidar-a2",
     "Slamtec RPLIDAR A2M8: 360 deg / 1 deg / 12 m triangulation, ~1% of range; sees glass rarely",
     {359.0, 1.0, 12.0, 10.0},
     {0.005, 0.01, 0.03, 0.01, 0.02, 1.0},
     {0.3, 1.0, 0.0, 2.0, 0.05, 1.5}},
    {"sick-tim571",
     "SICK TiM571: 270 deg / 0.33 deg / 25 m, 850 nm pulsed (HDDM+), 20 mm 1-sigma; widest lobe",
     {270.0, 1.0 / 3.0, 25.0, 15.0},
     {0.02, 0.0, 0.005, 0.002, 0.015, 1.5},
     {0.9, 20.0, 0.15, 1.0, 0.30, 1.5}},
};

SensorProfile make(const std::string& name, const std::string& description, const Geometry& g, const Noise& n,
                   const Response& r) {
  SensorProfile p;
  p.name = name;
  p.description = description;
  LaserSpec& l = p.laser;
  l.model = name;
  l.fov = deg2rad(g.fov_deg);
  l.resolution = deg2rad(g.resolution_deg);
  l.max_range = g.max_range;
  l.rate = g.rate;
  l.range_sigma = n.sigma;
  l.range_sigma_rel = n.sigma_rel;
  l.dropout_rate = n.dropout;
  l.random_rate = n.random;
  l.short_rate = n.short_rate;
  l.short_lambda = n.short_lambda;
  GlassPhysics& gl = p.glass;
  gl.direct_peak = r.peak;
  gl.direct_sigma_deg = r.sigma_deg;
  gl.direct_floor = r.floor;
  gl.reflection_gain = r.gain;
  gl.reflection_floor = r.reflection_floor;
  gl.n_glass = r.n_glass;
  return p;
}

SensorProfile randomProfile(const std::string& name, std::uint64_t seed) {
  SplitMix d(seed);  // the same draws on every platform
  const Named& base = kProfiles[d.next() % std::size(kProfiles)];
  Noise n;
  n.sigma = d.uniform(0.003, 0.03);
  n.sigma_rel = d.uniform(0.0, 0.012);
  n.dropout = d.uniform(0.0, 0.03);
  n.random = d.uniform(0.0, 0.01);
  n.short_rate = d.uniform(0.0, 0.03);
  n.short_lambda = d.uniform(0.5, 3.0);
  Response r;
  r.peak = d.uniform(0.3, 1.0);
  r.sigma_deg = d.uniform(1.0, 20.0);
  r.floor = d.uniform(0.0, 0.15);
  r.gain = d.uniform(0.5, 3.0);
  r.reflection_floor = d.uniform(0.0, 0.9);
  r.n_glass = d.uniform(1.47, 1.55);
  return make(name, std::string("random profile on the geometry of ") + base.name, base.geometry, n, r);
}

std::string nameList() {
  std::string out;
  for (const Named& p : kProfiles) out += std::string(out.empty() ? "" : ", ") + p.name;
  return out + ", random:SEED";
}

void check(bool ok, const char* what, const std::string& file, const char* field) {
  if (!ok) throw Error(what, file, 0, field);
}

}  // namespace

std::vector<std::string> sensorProfileNames() {
  std::vector<std::string> names;
  for (const Named& p : kProfiles) names.emplace_back(p.name);
  return names;
}

SensorProfile sensorProfile(const std::string& name, const std::string& field) {
  for (const Named& p : kProfiles)
    if (name == p.name) return make(p.name, p.description, p.geometry, p.noise, p.glass);
  const std::string prefix = "random:";
  if (name.rfind(prefix, 0) == 0) {
    const char* first = name.data() + prefix.size();
    const char* last = name.data() + name.size();
    std::uint64_t seed = 0;
    const auto [end, ec] = std::from_chars(first, last, seed);
    if (first != last && ec == std::errc() && end == last) return randomProfile(name, seed);
    throw Error("bad sensor profile '" + name + "': expected random:SEED with SEED a non-negative integer", {}, 0,
                field);
  }
  throw Error("unknown sensor profile '" + name + "' (expected one of " + nameList() + ")", {}, 0, field);
}

void applySensorProfile(Scene& scene, const SensorProfile& profile) {
  const Pose2 mount = scene.laser.T_base_laser;
  const int bounces = scene.glass.max_bounces;
  scene.laser = profile.laser;
  scene.laser.T_base_laser = mount;
  scene.glass = profile.glass;
  scene.glass.max_bounces = bounces;
  scene.sensor = profile.name;
}

void validateSensor(const LaserSpec& l, const GlassPhysics& g, const std::string& file) {
  check(l.fov > 0 && l.resolution > 0 && l.max_range > 0 && l.rate > 0,
        "laser fov, resolution, max_range and rate must be positive", file, "laser");
  check(l.range_sigma >= 0 && l.range_sigma_rel >= 0, "range noise must be >= 0", file, "laser.range_sigma");
  const auto rate = [](double p) { return p >= 0 && p <= 1; };
  check(rate(l.dropout_rate) && rate(l.random_rate) && rate(l.short_rate) &&
            l.dropout_rate + l.random_rate + l.short_rate <= 1,
        "dropout_rate, random_rate and short_rate must be in [0, 1] and sum to at most 1", file, "laser");
  check(l.short_lambda >= 0, "short_lambda must be >= 0", file, "laser.short_lambda");
  check(g.direct_floor >= 0 && g.direct_floor <= g.direct_peak && g.direct_peak <= 1,
        "expected 0 <= direct_floor <= direct_peak <= 1", file, "glass.direct_peak");
  check(g.direct_sigma_deg > 0, "direct_sigma_deg must be positive", file, "glass.direct_sigma_deg");
  check(g.reflection_gain >= 0 && rate(g.reflection_floor), "reflection_gain >= 0, reflection_floor in [0, 1] expected",
        file, "glass.reflection_floor");
  check(g.n_glass >= 1, "n_glass must be >= 1", file, "glass.n_glass");
  check(g.pane_thickness >= 0, "pane_thickness must be >= 0 (0 = the map's)", file, "glass.pane_thickness");
  check(g.max_bounces >= 0, "max_bounces must be >= 0", file, "glass.max_bounces");
}

}  // namespace glassmap::sim
