#pragma once
/// The laser simulator: runs a scene and returns a CARMEN-ready log with ground truth.

#include <array>
#include <cstdint>
#include <vector>

#include "glassmap/io/laser_scan.hpp"
#include "glassmap/sim/scene.hpp"

namespace glassmap::sim {

/// What physically happened to one beam (ground truth).
enum class BeamOutcome : std::uint8_t {
  Wall = 0,          ///< returned from an opaque surface seen directly
  GlassDirect,       ///< direct reflection off a pane back to the sensor (range to the glass)
  GlassReflected,    ///< specular reflection off glass, returned from beyond (phantom)
  GlassTransmitted,  ///< passed through one or more panes, returned from beyond (elongated)
  Person,            ///< cut short by a person
  MaxRange,          ///< nothing within max range (reading = max range)
  kCount
};

/// Name of an outcome ("wall", "glass_direct", ...).
const char* toString(BeamOutcome o);

/// Options of one run.
struct SimOptions {
  std::uint64_t seed = 1;
  double duration_limit = 0.0;  ///< stop after this many seconds, 0 = whole trajectory [s]
  bool repeat_until_limit = false;  ///< loop the trajectory until duration_limit
};

/// The result of a run.
struct SimResult {
  LaserLog log;                             ///< scans (laser_pose = SLAM-like, odom_pose = odometry) + ODOM
  std::vector<StampedPose> ground_truth;    ///< true laser pose per scan
  std::vector<std::vector<BeamOutcome>> outcomes;  ///< per scan, per beam
  std::array<std::size_t, static_cast<std::size_t>(BeamOutcome::kCount)> counts{};  ///< per outcome
};

/// Simulates the scene's trajectory with its laser, physics and noise. Deterministic for a seed.
SimResult simulate(const Scene& scene, const SimOptions& options = {});

}  // namespace glassmap::sim
