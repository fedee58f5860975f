#include "glassmap/sim/scene.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <limits>

#include "glassmap/core/error.hpp"
#include "glassmap/io/floorplan.hpp"
#include "glassmap/sim/sensor_profile.hpp"

namespace glassmap::sim {
namespace {

// Reads an optional scalar `key` of node into value; errors name the file, line and key.
template <typename T>
void read(const YAML::Node& node, const char* key, T& value, const std::string& file) {
  const YAML::Node v = node[key];
  if (!v) return;
  try {
    value = v.as<T>();
  } catch (const YAML::Exception&) {
    throw Error("expected a value of the right type", file, static_cast<std::size_t>(v.Mark().line + 1), key);
  }
}

void readDegrees(const YAML::Node& node, const char* key, double& radians, const std::string& file) {
  double deg = rad2deg(radians);
  read(node, key, deg, file);
  radians = deg2rad(deg);
}

}  // namespace

LaserSpec laserPreset(const std::string& name) {
  LaserSpec spec;
  spec.model = name;
  if (name == "hokuyo-utm30lx") {
    // Hokuyo UTM-30LX: 270 deg, 0.25 deg steps (1081 beams), 30 m, 40 Hz, +-3 cm accuracy.
    spec.fov = deg2rad(270.0);
    spec.resolution = deg2rad(0.25);
    spec.max_range = 30.0;
    spec.rate = 40.0;
    spec.range_sigma = 0.01;
  } else if (name == "sick-lms200") {
    // SICK LMS200: 180 deg, 1 deg steps (181 beams), 8 m mode of 80 m class, 75 Hz max; mm mode sigma ~1 cm.
    spec.fov = deg2rad(180.0);
    spec.resolution = deg2rad(1.0);
    spec.max_range = 8.0 * 10.0;  // 80 m in cm mode; indoor logs usually show 8.183 m or 81.83 m
    spec.rate = 37.5;
    spec.range_sigma = 0.01;
  } else {
    throw Error("unknown laser preset '" + name + "' (expected hokuyo-utm30lx or sick-lms200)", {}, 0, "laser.preset");
  }
  return spec;
}

Scene loadScene(const std::filesystem::path& yaml) {
  const std::string file = yaml.string();
  YAML::Node root;
  try {
    root = YAML::LoadFile(file);
  } catch (const YAML::BadFile&) {
    throw Error("cannot open scene file", file);
  } catch (const YAML::ParserException& e) {
    throw Error(e.msg, file, static_cast<std::size_t>(e.mark.line + 1));
  }
  if (!root.IsMap()) throw Error("expected a YAML mapping", file, 1);

  Scene scene;
  scene.name = yaml.parent_path().filename().string();
  read(root, "name", scene.name, file);

  std::string floorplan;
  read(root, "floorplan", floorplan, file);
  if (floorplan.empty()) throw Error("missing key", file, 0, "floorplan");
  scene.floorplan_path = yaml.parent_path() / floorplan;
  scene.map = readFloorplan(scene.floorplan_path);
  scene.map.name = scene.name;

  // The laser: a sensor profile (top-level `sensor:` or `laser: {sensor: ...}`) or a preset, then
  // the explicit fields.
  const YAML::Node l = root["laser"];
  std::string sensor, laser_sensor;
  read(root, "sensor", sensor, file);
  if (l) read(l, "sensor", laser_sensor, file);
  if (!sensor.empty() && !laser_sensor.empty() && sensor != laser_sensor)
    throw Error("sensor and laser.sensor name different profiles", file, 0, "sensor");
  if (sensor.empty()) sensor = laser_sensor;
  if (!sensor.empty()) {
    if (l && l["preset"]) throw Error("give laser.preset or a sensor profile, not both", file, 0, "laser.preset");
    try {
      applySensorProfile(scene, sensorProfile(sensor));
    } catch (const Error& e) {
      const YAML::Node at = root["sensor"] ? root["sensor"] : l["sensor"];
      throw Error(e.message(), file, static_cast<std::size_t>(at.Mark().line + 1), e.field());
    }
  }
  if (l) {
    if (sensor.empty()) {
      std::string preset = scene.laser.model;
      read(l, "preset", preset, file);
      scene.laser = laserPreset(preset);
    }
    readDegrees(l, "fov_deg", scene.laser.fov, file);
    readDegrees(l, "resolution_deg", scene.laser.resolution, file);
    read(l, "max_range", scene.laser.max_range, file);
    read(l, "rate", scene.laser.rate, file);
    read(l, "range_sigma", scene.laser.range_sigma, file);
    read(l, "range_sigma_rel", scene.laser.range_sigma_rel, file);
    read(l, "dropout_rate", scene.laser.dropout_rate, file);
    read(l, "random_rate", scene.laser.random_rate, file);
    read(l, "short_rate", scene.laser.short_rate, file);
    read(l, "short_lambda", scene.laser.short_lambda, file);
    if (const YAML::Node m = l["mount"]) {  // [x, y, theta_deg]: the laser on the robot
      if (!m.IsSequence() || m.size() != 3)
        throw Error("expected [x, y, theta_deg]", file, static_cast<std::size_t>(m.Mark().line + 1), "laser.mount");
      try {
        scene.laser.T_base_laser = Pose2(m[0].as<double>(), m[1].as<double>(), deg2rad(m[2].as<double>()));
      } catch (const YAML::Exception&) {
        throw Error("expected [x, y, theta_deg]", file, static_cast<std::size_t>(m.Mark().line + 1), "laser.mount");
      }
    }
  }

  const YAML::Node t = root["trajectory"];
  if (!t || !t["waypoints"] || !t["waypoints"].IsSequence())
    throw Error("missing waypoint list", file, 0, "trajectory.waypoints");
  for (const YAML::Node& w : t["waypoints"]) {
    if (!w.IsSequence() || w.size() != 2)
      throw Error("expected [x, y]", file, static_cast<std::size_t>(w.Mark().line + 1), "trajectory.waypoints");
    scene.trajectory.waypoints.emplace_back(w[0].as<double>(), w[1].as<double>());
  }
  if (scene.trajectory.waypoints.size() < 2)
    throw Error("need at least two waypoints", file, 0, "trajectory.waypoints");
  read(t, "round_trip", scene.trajectory.round_trip, file);
  read(t, "speed", scene.trajectory.speed, file);
  readDegrees(t, "turn_rate_deg", scene.trajectory.turn_rate, file);
  scene.trajectory.start_heading = std::numeric_limits<double>::quiet_NaN();
  if (t["start_heading_deg"]) {
    double deg = 0;
    read(t, "start_heading_deg", deg, file);
    scene.trajectory.start_heading = deg2rad(deg);
  }
  if (scene.trajectory.speed <= 0 || scene.trajectory.turn_rate <= 0)
    throw Error("speed and turn rate must be positive", file, 0, "trajectory");

  if (const YAML::Node g = root["glass"]) {
    read(g, "n_glass", scene.glass.n_glass, file);
    read(g, "direct_sigma_deg", scene.glass.direct_sigma_deg, file);
    read(g, "direct_peak", scene.glass.direct_peak, file);
    read(g, "direct_floor", scene.glass.direct_floor, file);
    read(g, "reflection_gain", scene.glass.reflection_gain, file);
    read(g, "reflection_floor", scene.glass.reflection_floor, file);
    read(g, "pane_thickness", scene.glass.pane_thickness, file);
    read(g, "max_bounces", scene.glass.max_bounces, file);
  }
  validateSensor(scene.laser, scene.glass, file);
  if (const YAML::Node m = root["motion"]) {
    read(m, "odom_trans_sigma", scene.motion.odom_trans_sigma, file);
    read(m, "odom_rot_sigma", scene.motion.odom_rot_sigma, file);
    read(m, "odom_rot_per_m", scene.motion.odom_rot_per_m, file);
    read(m, "odom_scale_bias", scene.motion.odom_scale_bias, file);
    double drift_deg = rad2deg(scene.motion.odom_drift_per_m);
    read(m, "odom_drift_deg_per_m", drift_deg, file);
    scene.motion.odom_drift_per_m = deg2rad(drift_deg);
    read(m, "slam_sigma_xy", scene.motion.slam_sigma_xy, file);
    readDegrees(m, "slam_sigma_theta_deg", scene.motion.slam_sigma_theta, file);
  }
  if (const YAML::Node p = root["people"]) {
    read(p, "density", scene.people.density, file);
    read(p, "radius", scene.people.radius, file);
    read(p, "speed", scene.people.speed, file);
    read(p, "group_size", scene.people.group_size, file);
    if (scene.people.density < 0 || scene.people.radius <= 0 || scene.people.group_size < 1)
      throw Error("people density >= 0, radius > 0, group_size >= 1 expected", file, 0, "people");
  }
  return scene;
}

}  // namespace glassmap::sim
