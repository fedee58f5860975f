#pragma once
/// A simulation scene: floorplan, trajectory, laser and noise, read from one small YAML file.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "glassmap/core/pose2.hpp"
#include "glassmap/geometry/vector_map.hpp"

namespace glassmap::sim {

/// A 2D laser scanner: geometry, range noise and spurious readings (Probabilistic Robotics 6.3:
/// max-range dropouts, uniform random readings, short readings). The default is the
/// "hokuyo-utm30lx" preset, without spurious readings.
struct LaserSpec {
  std::string model = "hokuyo-utm30lx";  ///< preset or sensor profile name
  double fov = deg2rad(270.0);           ///< field of view [rad]
  double resolution = deg2rad(0.25);     ///< angle between beams [rad]
  double max_range = 30.0;               ///< [m]
  double rate = 40.0;                    ///< scans per second [Hz]
  double range_sigma = 0.01;             ///< Gaussian range noise [m]
  double range_sigma_rel = 0.0;  ///< noise growing with range: sigma(r) = hypot(range_sigma, range_sigma_rel r) [-]
  double dropout_rate = 0.0;     ///< P(a beam that meets a surface reads max range) [-]
  double random_rate = 0.0;      ///< P(a reading uniform in [0, max_range)) [-]
  double short_rate = 0.0;       ///< P(a reading short of the surface: mixed pixel, dust) [-]
  double short_lambda = 1.0;     ///< short readings: density ~ exp(-short_lambda z) on [0, true range];
                                 ///< 0 = uniform there [1/m]
  Pose2 T_base_laser;            ///< laser mounting on the robot
};

/// Laser presets (geometry and noise only): "hokuyo-utm30lx", "sick-lms200". Throws Error for an
/// unknown name. Full sensor profiles (spurious readings, glass response) are in sensor_profile.hpp.
LaserSpec laserPreset(const std::string& name);

/// How glass acts on the beam (physics, not the sensor model we fit later). At each pane met at
/// incidence theta: P(direct) = direct_floor + (direct_peak - direct_floor) exp(-theta^2 / 2 sigma^2);
/// otherwise P(specular) = max(reflection_floor, min(1, reflection_gain R(theta))), R the
/// unpolarised Fresnel reflectance; otherwise the beam goes through.
struct GlassPhysics {
  double n_glass = 1.5;           ///< refractive index of the panes
  double direct_sigma_deg = 2.0;  ///< sigma of the direct-return lobe over incidence angle [deg]
  double direct_peak = 0.9;       ///< probability of a direct return at normal incidence
  double direct_floor = 0.0;      ///< probability of a direct return at any incidence [-]
  double reflection_gain = 1.0;   ///< P(specular) >= min(1, gain * unpolarised Fresnel reflectance)
  double reflection_floor = 0.0;  ///< P(specular) >= this at any incidence, when not returned directly [-]
  double pane_thickness = 0.0;    ///< every pane's thickness for the elongation [m]; 0 = the map's
  int max_bounces = 4;            ///< reflections/transmissions followed per beam
};

/// Odometry and SLAM-pose noise.
struct MotionNoise {
  // Random-walk noise: standard deviations after 1 m travelled or 1 rad turned.
  double odom_trans_sigma = 0.01;          ///< translation noise [m per sqrt(m)]
  double odom_rot_sigma = 0.01;            ///< heading noise from turning [rad per sqrt(rad)]
  double odom_rot_per_m = 0.005;           ///< heading noise from driving [rad per sqrt(m)]
  double odom_scale_bias = 0.0;            ///< systematic scale error (0.02 = odometry reads 2% long)
  double odom_drift_per_m = 0.0;           ///< systematic heading drift [rad/m]
  double slam_sigma_xy = 0.01;             ///< noise of the logged (SLAM) laser pose [m]
  double slam_sigma_theta = deg2rad(0.2);  ///< [rad]
};

/// People walking through the scene: discs that cut beams short.
struct PeopleSpec {
  double density = 0.0;  ///< people per 100 m^2 of the floor's bounding box
  double radius = 0.25;  ///< [m]
  double speed = 1.0;    ///< [m/s]
  int group_size = 1;    ///< people walking together
};

/// Trajectory: waypoints driven in order, turning in place at each.
struct TrajectorySpec {
  std::vector<Vec2> waypoints;       ///< [m]
  bool round_trip = false;           ///< drive back to the start along the same waypoints
  double speed = 0.5;                ///< [m/s]
  double turn_rate = deg2rad(45.0);  ///< [rad/s]
  double start_heading = 0.0;        ///< [rad]; NaN heads to the first waypoint
};

/// Everything a simulation needs.
struct Scene {
  std::string name;
  VectorMap map;
  TrajectorySpec trajectory;
  LaserSpec laser;
  GlassPhysics glass;
  std::string sensor;  ///< sensor profile the laser and glass response come from; empty = laser preset
  MotionNoise motion;
  PeopleSpec people;
  std::filesystem::path floorplan_path;  ///< where map was read from
};

/// Reads a scene YAML (see maps/README.md); the floorplan path is relative to the YAML. A `sensor:`
/// key (top level or in `laser:`) picks a sensor profile; explicit laser and glass keys override it.
Scene loadScene(const std::filesystem::path& yaml);

}  // namespace glassmap::sim
