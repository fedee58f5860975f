#pragma once
/// The laser simulator: runs a scene and returns a CARMEN-ready log with ground truth.

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "glassmap/core/laser_scan.hpp"
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
  Dropout,           ///< spurious: a beam that met a surface read max range
  Short,             ///< spurious: a reading short of the surface (mixed pixel, dust)
  Random,            ///< spurious: a reading uniform in [0, max range)
  kCount
};

/// Name of an outcome ("wall", "glass_direct", ...).
const char* toString(BeamOutcome o);

/// A kidnapping: the robot is carried to another pose at one instant and the odometry records no
/// motion for it (the wheels do not turn); afterwards the odometry integrates the real motion again
/// from where it believed the robot was.
struct Kidnap {
  double time = -1.0;       ///< when [s]: the first scan at or after it sees the new pose; < 0 = never
  double along = 0.0;       ///< jump this far ahead along the trajectory, which goes on from there [m]
  std::optional<Pose2> to;  ///< or: jump to this base pose; the rest of the trajectory moves rigidly
                            ///< with it (it is up to the caller that it stays in free space)
};

/// Options of one run.
struct SimOptions {
  std::uint64_t seed = 1;
  double duration_limit = 0.0;      ///< stop after this many seconds, 0 = whole trajectory [s]
  bool repeat_until_limit = false;  ///< loop the trajectory until duration_limit
  Kidnap kidnap{};                  ///< none by default
};

/// What a kidnapping did (ground truth).
struct KidnapEvent {
  std::size_t scan = 0;  ///< index of the first scan at the new pose
  double time = 0.0;     ///< its timestamp [s]
  Pose2 from;            ///< true T_map_laser the robot would have had at that scan without it
  Pose2 to;              ///< true T_map_laser it had instead
  double distance() const { return (to.t - from.t).norm(); }  ///< [m]
};

/// The result of a run.
struct SimResult {
  LaserLog log;                                    ///< scans (laser_pose = SLAM-like, odom_pose = odometry) + ODOM
  std::vector<StampedPose> ground_truth;           ///< true laser pose per scan
  std::vector<std::vector<BeamOutcome>> outcomes;  ///< per scan, per beam
  std::array<std::size_t, static_cast<std::size_t>(BeamOutcome::kCount)> counts{};  ///< per outcome
  std::optional<KidnapEvent> kidnap;  ///< set when options.kidnap happened
};

/// Simulates the scene's trajectory with its laser, physics and noise. Deterministic for a seed.
/// Throws Error for a kidnapping at time <= 0, past the end of the run, or (along) past the end
/// of a trajectory driven once.
SimResult simulate(const Scene& scene, const SimOptions& options = {});

}  // namespace glassmap::sim
