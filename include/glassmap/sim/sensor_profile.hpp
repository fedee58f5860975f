#pragma once
/// Sensor profiles: a real scanner's geometry, range noise, spurious readings and glass response,
/// by name. The numbers and their sources are in maps/README.md, "Sensor profiles".

#include <cstdint>
#include <string>
#include <vector>

#include "glassmap/sim/scene.hpp"

namespace glassmap::sim {

/// A complete simulated sensor: the laser (geometry, noise, spurious readings) and how its beam
/// acts on glass (direct-return lobe and floor, specular reflection, refractive index).
struct SensorProfile {
  std::string name;         ///< "sick-lms200", ..., or "random:SEED"
  std::string description;  ///< what it models, one line
  LaserSpec laser;          ///< laser.model = name; T_base_laser identity
  GlassPhysics glass;       ///< pane_thickness 0 (the map's) and max_bounces 4 in every profile
};

/// Names of the named profiles, in a fixed order (random:SEED is not among them).
std::vector<std::string> sensorProfileNames();

/// The profile `name`, or for "random:SEED" (SEED a decimal integer) one drawn reproducibly: the
/// geometry of a named profile, the other numbers uniform in the ranges the named ones span
/// (range_sigma 0.003-0.03 m, range_sigma_rel 0-0.012, dropout 0-0.03, random 0-0.01, short
/// 0-0.03, short_lambda 0.5-3 /m, direct_peak 0.3-1, direct_sigma_deg 1-20, direct_floor 0-0.15,
/// reflection_gain 0.5-3, reflection_floor 0-0.9, n_glass 1.47-1.55). Throws Error naming `field`
/// for an unknown name.
SensorProfile sensorProfile(const std::string& name, const std::string& field = "sensor");

/// Gives the scene the profile's laser (keeping the mounting T_base_laser) and glass response
/// (keeping max_bounces); records the name in scene.sensor.
void applySensorProfile(Scene& scene, const SensorProfile& profile);

/// Throws Error (naming `file` and the field) when a laser or glass number is out of range:
/// geometry and rate positive, noise >= 0, rates in [0, 1] summing to at most 1, direct_floor <=
/// direct_peak <= 1, reflection_floor in [0, 1], n_glass >= 1, thickness >= 0.
void validateSensor(const LaserSpec& laser, const GlassPhysics& glass, const std::string& file = {});

}  // namespace glassmap::sim
