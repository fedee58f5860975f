#pragma once
/// A simulation scene: floorplan, trajectory, laser and noise, read from one small YAML file.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "glassmap/core/pose2.hpp"
#include "glassmap/geometry/vector_map.hpp"

namespace glassmap::sim {

/// A 2D laser scanner.
struct LaserSpec {
  std::string model = "hokuyo-utm30lx";  ///< preset name
  double fov = deg2rad(270.0);           ///< field of view [rad]
  double resolution = deg2rad(0.25);     ///< angle between beams [rad]
  double max_range = 30.0;               ///< [m]
  double rate = 40.0;                    ///< scans per second [Hz]
  double range_sigma = 0.01;             ///< Gaussian range noise [m]
  Pose2 T_base_laser;                    ///< laser mounting on the robot
};

/// Laser presets: "hokuyo-utm30lx", "sick-lms200". Throws Error for an unknown name.
LaserSpec laserPreset(const std::string& name);

/// How glass acts on the beam (physics, not the sensor model we fit later).
struct GlassPhysics {
  double n_glass = 1.5;           ///< refractive index of the panes
  double direct_sigma_deg = 2.0;  ///< sigma of the direct-return lobe over incidence angle [deg]
  double direct_peak = 0.9;       ///< probability of a direct return at normal incidence
  double reflection_gain = 1.0;   ///< P(specular) = min(1, gain * unpolarised Fresnel reflectance)
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
  MotionNoise motion;
  PeopleSpec people;
  std::filesystem::path floorplan_path;  ///< where map was read from
};

/// Reads a scene YAML (see maps/README.md); the floorplan path is relative to the YAML.
Scene loadScene(const std::filesystem::path& yaml);

}  // namespace glassmap::sim
