#pragma once
/// Trajectory accuracy against ground truth (absolute trajectory error, as evo's `ape` prints it
/// without alignment: both trajectories are in the map frame).

#include <vector>

#include "glassmap/core/laser_scan.hpp"

namespace glassmap::eval {

/// Options of the comparison.
struct TrajectoryEvalOptions {
  double max_time_diff = 0.01;  ///< an estimate is matched to the nearest truth pose within this [s]
  double good_error = 0.2;      ///< threshold of the "fraction under" figure [m]
};

/// Errors of an estimated trajectory; position figures in [m], heading in [deg].
struct TrajectoryErrors {
  std::size_t matched = 0;    ///< estimates matched to a truth pose
  std::size_t unmatched = 0;  ///< estimates with no truth pose within max_time_diff
  double rmse = 0, mean = 0, median = 0, std = 0, min = 0, max = 0;  ///< position error [m]
  double heading_mean_deg = 0;                                       ///< mean absolute heading error [deg]
  double heading_max_deg = 0;                                        ///< largest absolute heading error [deg]
  double fraction_under = 0;               ///< fraction of the matched time with error < good_error [-]
  double good_error = 0.2;                 ///< the threshold used [m]
  std::vector<double> times;               ///< timestamp of each matched estimate [s]
  std::vector<double> position_errors;     ///< [m]
  std::vector<double> heading_errors_deg;  ///< absolute [deg]
};

/// Matches each estimate to the truth pose nearest in time and summarises the errors. Throws
/// Error when nothing matches.
TrajectoryErrors evaluateTrajectory(const std::vector<StampedPose>& truth, const std::vector<StampedPose>& estimate,
                                    const TrajectoryEvalOptions& options = {});

}  // namespace glassmap::eval
