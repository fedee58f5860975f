#pragma once
/// The part of a true floorplan that a robot could have seen. A map can only hold what its log saw;
/// scoring recall against walls the robot never faced measures the trajectory, not the mapper. These
/// functions cut the truth down to what some laser pose of the log had in line of sight.

#include <vector>

#include "glassmap/core/laser_scan.hpp"
#include "glassmap/core/pose2.hpp"
#include "glassmap/geometry/vector_map.hpp"

namespace glassmap::eval {

/// A place the truth was looked at from: a laser pose, its field of view and its range.
struct Viewpoint {
  Pose2 pose;                ///< laser pose in the map frame
  double start_angle = 0.0;  ///< first beam in the laser frame [rad]
  double span = 0.0;         ///< field of view [rad]
  double max_range = 0.0;    ///< [m]
};

/// Laser poses of a log at least `spacing` apart or turned by more than 10 degrees, each with its
/// scan's field of view and range (capped at range_cap).
std::vector<Viewpoint> viewpointsOfLog(const LaserLog& log, double spacing = 0.25, double range_cap = 30.0);

/// The parts of `truth` in line of sight of some viewpoint: within its field of view and range, and
/// no wall in between (glass is see-through: the laser reads what lies behind most panes). Every
/// segment is sampled every `step`; each run of visible samples becomes a segment with the
/// original's attributes.
VectorMap visiblePart(const VectorMap& truth, const std::vector<Viewpoint>& viewpoints, double step = 0.02);

}  // namespace glassmap::eval
