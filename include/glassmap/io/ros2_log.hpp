#pragma once
/// Laser logs as ROS 2 bags: reading a bag's scans with their poses from the transform tree
/// (readLog in log.hpp calls readRos2Log), writing a LaserLog as a bag, and summarising a bag.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "glassmap/core/laser_scan.hpp"
#include "glassmap/io/log.hpp"
#include "glassmap/io/ros2_bag.hpp"

namespace glassmap {

/// Reads the scans of a bag (see readLog): scan topic and poses as Ros2LogOptions say.
LaserLog readRos2Log(const std::filesystem::path& path, const LogReadOptions& options = {},
                     LogReadNotes* notes = nullptr);

/// Topics and frames of a bag written from a log.
struct Ros2LogFrames {
  std::string scan_topic = "/scan";  ///< laser 1 (or the first laser); laser k > 1 -> "<scan_topic>_<k>"
  std::string odom_topic = "/odom";
  std::string map_frame = "map";
  std::string odom_frame = "odom";
  std::string base_frame = "base_link";
  std::string laser_frame = "laser";  ///< laser k > 1 -> "<laser_frame>_<k>"
};

/// What writeRos2Log wrote.
struct Ros2LogWriteResult {
  std::size_t scans = 0, odometry = 0, tf_messages = 0;
  std::vector<std::string> notes;  ///< what the bag cannot hold (true poses, PARAM lines)
};

/// Writes a log as a rosbag2 bag directory `path` (see ros2::BagWriter): the scans as
/// sensor_msgs/msg/LaserScan in the laser frame (no-returns as +inf, range_min 0), the ODOM
/// records (else each scan's odometry pose) as nav_msgs/msg/Odometry odom -> base_link, per scan
/// one /tf message with odom -> base_link (the scan's odometry pose) and map -> odom chosen so that
/// map -> laser is the scan's laser pose, and one /tf_static message base_link -> laser (identity).
/// Stamps are the scans' timestamps to the nanosecond. Throws Error when the log has no scan.
Ros2LogWriteResult writeRos2Log(const LaserLog& log, const std::filesystem::path& path,
                                const ros2::BagWriteOptions& options = {}, const Ros2LogFrames& frames = {});

/// What `glassmap info` says about a bag.
struct Ros2BagSummary {
  std::vector<std::filesystem::path> files;
  ros2::BagStorage storage = ros2::BagStorage::Mcap;
  std::vector<ros2::BagTopic> topics;
  std::uint64_t messages = 0;
  double t_first = 0.0, t_last = 0.0;  ///< log times of the first and last message [s]
  /// One parent -> child edge of /tf and /tf_static.
  struct Transform {
    std::string parent, child;
    bool is_static = false;
    std::size_t samples = 0;
  };
  std::vector<Transform> transforms;
  std::vector<std::string> scan_frames;  ///< header.frame_id of the scan topics' messages
  double max_tilt = 0.0;                 ///< largest roll/pitch of any transform [rad]
  std::vector<std::string> notes;        ///< what the storage reader found, and messages that did not decode
  double duration() const { return t_last - t_first; }  ///< [s]
};

/// Reads every message's time and decodes the transforms and the scans' frames (messages that do
/// not decode are counted in the notes, not an error: info is for looking at broken bags too).
Ros2BagSummary summarizeRos2Bag(const std::filesystem::path& path);

}  // namespace glassmap
