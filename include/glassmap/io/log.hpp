#pragma once
/// Laser logs of any supported kind: CARMEN logs (plain or gzip) and ROS 2 bags (a rosbag2
/// directory, a .db3 or a .mcap file), told apart by content.

#include <filesystem>
#include <string>
#include <vector>

#include "glassmap/core/laser_scan.hpp"
#include "glassmap/io/carmen.hpp"

namespace glassmap {

/// Where the laser pose of a scan read from a bag comes from.
enum class BagPoseSource {
  Auto,      ///< map -> odom -> base -> laser when the bag has a map -> odom transform, else odometry
  Map,       ///< require map -> odom (error when the bag has none)
  Odometry,  ///< odom -> base -> laser only (what localization wants)
};

/// How a ROS 2 bag becomes a LaserLog.
struct Ros2LogOptions {
  std::string scan_topic;          ///< "" = the only LaserScan topic (error naming them when several)
  std::string odom_topic;          ///< nav_msgs/Odometry topic; "" = the only one, if any
  std::string map_frame = "map";   ///< frame of SLAM-corrected poses
  std::string odom_frame = "odom"; ///< odometry frame
  std::string base_frame;          ///< robot frame; "" = child_frame_id of the odometry, else "base_link"
  BagPoseSource pose_source = BagPoseSource::Auto;
};

/// Options of readLog: the CARMEN reader's (laser_id, flaser_max_range, require_scans,
/// max_memory_bytes, progress also apply to bags where they make sense) and the bag's.
struct LogReadOptions {
  CarmenReadOptions carmen;
  Ros2LogOptions ros2;
};

/// What readLog found out about where the poses came from (for a bag: which transforms were
/// used and what was assumed), to print on stderr; empty for CARMEN logs.
struct LogReadNotes {
  std::vector<std::string> notes;     ///< e.g. "laser poses from map -> odom (slam_toolbox) -> base_link -> laser"
  std::vector<std::string> warnings;  ///< e.g. "no map -> odom transform: laser poses from odometry alone"
};

/// True when `path` is a ROS 2 bag (see ros2::isBag).
bool isRos2Bag(const std::filesystem::path& path);

/// Reads a whole log, CARMEN or ROS 2 bag. For a bag: each scan's laser_pose is the laser's pose
/// composed from the transform tree at the scan's stamp (interpolated), odom_pose the robot's
/// odometry pose at that stamp (has_odom when there is odometry or an odom -> base transform).
LaserLog readLog(const std::filesystem::path& path, const LogReadOptions& options = {},
                 LogReadNotes* notes = nullptr);

}  // namespace glassmap
