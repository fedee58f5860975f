#pragma once
/// Figures about a laser log (what `glassmap info` prints), computed while streaming the log.

#include <cstddef>
#include <filesystem>
#include <map>

#include "glassmap/geometry/vector_map.hpp"
#include "glassmap/io/carmen.hpp"

namespace glassmap {

/// Summary of a laser log.
struct LogSummary {
  std::size_t scans = 0;
  std::size_t beams_min = 0, beams_max = 0;         ///< beams per scan
  double fov_min = 0.0, fov_max = 0.0;              ///< field of view covered by the beams [rad]
  double step_min = 0.0, step_max = 0.0;            ///< angle between beams [rad]
  double max_range_min = 0.0, max_range_max = 0.0;  ///< sensor maximum range [m]
  double longest_return = 0.0;                      ///< longest range below max range [m]
  std::size_t max_readings = 0;                     ///< ranges at or above the max range
  double t_first = 0.0, t_last = 0.0;               ///< first and last timestamp of any record [s]
  std::size_t time_reversals = 0;                   ///< scans stamped earlier than the scan before
  double distance = 0.0;                            ///< path length of the laser poses [m] (first laser)
  double odometry_distance = 0.0;                   ///< path length of the ODOM poses [m]
  Eigen::AlignedBox2d pose_bounds;                  ///< bounding box of the laser poses [m]
  std::map<int, std::size_t> scans_per_laser;       ///< laser id -> scans
  LogReadStats stats;                               ///< what the reader met (skipped types, no returns)

  double duration() const { return t_last - t_first; }  ///< [s]
};

/// Streams a CARMEN log (plain or gzip) and summarises it in bounded memory.
LogSummary summarizeCarmenLog(const std::filesystem::path& path, const CarmenReadOptions& options = {});

/// The same figures for a log in memory (e.g. a bag read through readLog); stats are the log's.
LogSummary summarizeLog(const LaserLog& log);

}  // namespace glassmap
