// A LaserLog written as a ROS 2 bag, and the summary of a bag (see ros2_log.hpp).
#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "glassmap/core/error.hpp"
#include "glassmap/io/ros2_cdr.hpp"
#include "glassmap/io/ros2_log.hpp"
#include "glassmap/io/ros2_tf.hpp"

namespace glassmap {

namespace fs = std::filesystem;

namespace {

ros2::TransformStampedMsg transform(const ros2::TimeMsg& stamp, const std::string& parent, const std::string& child,
                                    const Pose2& T) {
  ros2::TransformStampedMsg m;
  m.header.stamp = stamp;
  m.header.frame_id = parent;
  m.child_frame_id = child;
  m.translation = {T.x(), T.y(), 0.0};
  m.rotation = ros2::yawQuaternion(T.theta);
  return m;
}

std::string suffixed(const std::string& base, int laser_id, int first_id) {
  return laser_id == first_id ? base : base + "_" + std::to_string(laser_id);
}

}  // namespace

Ros2LogWriteResult writeRos2Log(const LaserLog& log, const fs::path& path, const ros2::BagWriteOptions& options,
                                const Ros2LogFrames& fr) {
  if (log.scans.empty()) throw Error("the log holds no scan to write", path.string());
  Ros2LogWriteResult result;
  ros2::BagWriter writer(path, options);
  const int first_id = log.scans.front().laser_id;
  std::map<int, int> scan_topic_ids;  // laser id -> bag topic id
  for (const LaserScan& s : log.scans)
    if (!scan_topic_ids.contains(s.laser_id))
      scan_topic_ids[s.laser_id] = writer.addTopic(suffixed(fr.scan_topic, s.laser_id, first_id), ros2::kLaserScanType,
                                                   ros2::messageDefinition(ros2::kLaserScanType));
  const int odom_id = writer.addTopic(fr.odom_topic, ros2::kOdometryType, ros2::messageDefinition(ros2::kOdometryType));
  const std::string tf_def = ros2::messageDefinition(ros2::kTFMessageType);
  const int tf_id = writer.addTopic("/tf", ros2::kTFMessageType, tf_def);
  const int tf_static_id = writer.addTopic("/tf_static", ros2::kTFMessageType, tf_def);

  // Header stamps keep the log's times (ROS 2 Time has signed seconds); log times of a bag cannot be
  // negative, so a log stamped from before 0 (relative CARMEN times) is shifted as a whole.
  double t_min = log.scans.front().timestamp;
  for (const LaserScan& s : log.scans) t_min = std::min(t_min, s.timestamp);
  for (const StampedPose& p : log.odometry) t_min = std::min(t_min, p.timestamp);
  const std::int64_t shift_ns = t_min < 0.0 ? -ros2::TimeMsg::fromSeconds(t_min).nanoseconds() : 0;
  auto logTime = [&](const ros2::TimeMsg& stamp) { return stamp.nanoseconds() + shift_ns; };
  if (shift_ns > 0)
    result.notes.push_back("the log has stamps before 0 (earliest " + std::to_string(t_min) +
                           " s): the bag's log times are the stamps plus " + std::to_string(1e-9 * shift_ns) +
                           " s; message header stamps keep the log's times");

  // /tf_static: base -> each laser, identity (the laser poses are carried by map -> odom)
  const ros2::TimeMsg t0 = ros2::TimeMsg::fromSeconds(log.scans.front().timestamp);
  ros2::TFMessageMsg statics;
  for (const auto& [id, topic] : scan_topic_ids)
    statics.transforms.push_back(transform(t0, fr.base_frame, suffixed(fr.laser_frame, id, first_id), Pose2()));
  writer.write(tf_static_id, logTime(t0), ros2::encode(statics));
  ++result.tf_messages;

  for (const LaserScan& s : log.scans) {
    const ros2::TimeMsg stamp = ros2::TimeMsg::fromSeconds(s.timestamp);
    ros2::LaserScanMsg m;
    m.header.stamp = stamp;
    m.header.frame_id = suffixed(fr.laser_frame, s.laser_id, first_id);
    m.angle_min = static_cast<float>(s.start_angle);
    m.angle_increment = static_cast<float>(s.angular_step);
    m.angle_max = static_cast<float>(s.start_angle + s.fieldOfView());
    m.range_min = 0.0f;
    m.range_max = static_cast<float>(s.max_range);
    m.ranges = s.ranges;  // kNoReturn is +inf: what REP 117 calls no return
    writer.write(scan_topic_ids.at(s.laser_id), logTime(stamp), ros2::encode(m));
    ++result.scans;

    // odom -> base = the odometry pose; map -> odom so that map -> odom -> base -> laser = laser pose
    const Pose2 T_odom_base = s.has_odom ? s.odom_pose : s.laser_pose;
    ros2::TFMessageMsg tf;
    if (s.has_laser_pose)
      tf.transforms.push_back(transform(stamp, fr.map_frame, fr.odom_frame, s.laser_pose * T_odom_base.inverse()));
    tf.transforms.push_back(transform(stamp, fr.odom_frame, fr.base_frame, T_odom_base));
    writer.write(tf_id, logTime(stamp), ros2::encode(tf));
    ++result.tf_messages;
  }

  auto writeOdom = [&](double t, const Pose2& pose, double tv, double rv) {
    ros2::OdometryMsg m;
    m.header.stamp = ros2::TimeMsg::fromSeconds(t);
    m.header.frame_id = fr.odom_frame;
    m.child_frame_id = fr.base_frame;
    m.position = {pose.x(), pose.y(), 0.0};
    m.orientation = ros2::yawQuaternion(pose.theta);
    m.linear = {tv, 0.0, 0.0};
    m.angular = {0.0, 0.0, rv};
    writer.write(odom_id, logTime(m.header.stamp), ros2::encode(m));
    ++result.odometry;
  };
  if (!log.odometry.empty()) {
    for (const StampedPose& p : log.odometry) writeOdom(p.timestamp, p.pose, p.tv, p.rv);
  } else {
    for (const LaserScan& s : log.scans)
      if (s.has_odom) writeOdom(s.timestamp, s.odom_pose, 0.0, 0.0);
  }
  writer.close();
  if (!log.true_poses.empty())
    result.notes.push_back(std::to_string(log.true_poses.size()) +
                           " true poses (TRUEPOS) not written: a bag has no "
                           "place for ground truth");
  if (!log.params.empty()) result.notes.push_back(std::to_string(log.params.size()) + " PARAM records not written");
  return result;
}

Ros2BagSummary summarizeRos2Bag(const fs::path& path) {
  const auto bag = ros2::openBag(path);
  Ros2BagSummary s;
  s.files = bag->files();
  s.storage = bag->storage();
  s.topics = bag->topics();
  std::set<std::string> readable;  // topics decoded: transforms and scans
  for (const ros2::BagTopic& t : s.topics) {
    if (t.serialization_format != "cdr") continue;
    if (t.type == ros2::kTFMessageType || t.type == ros2::kLaserScanType || t.type == ros2::kMultiEchoLaserScanType)
      readable.insert(t.name);
  }
  ros2::TfBuffer tf;
  std::map<std::pair<std::string, std::string>, std::size_t> samples;
  std::map<std::pair<std::string, std::string>, bool> statics;
  std::set<std::string> scan_frames;
  std::map<std::string, std::size_t> counters;
  std::size_t bad = 0;
  std::string first_error;
  auto decode = [&](const ros2::BagMessage& m, const std::string& where) {
    const std::string& name = m.topic->name;
    if (m.topic->type == ros2::kTFMessageType) {
      const ros2::TFMessageMsg msg = ros2::decodeTFMessage(m.data, where);
      const bool is_static = name.ends_with("tf_static");
      for (const auto& x : msg.transforms) {
        ++samples[{x.header.frame_id, x.child_frame_id}];
        statics[{x.header.frame_id, x.child_frame_id}] = is_static;
      }
      tf.add(msg, is_static);
    } else if (m.topic->type == ros2::kLaserScanType) {
      scan_frames.insert(ros2::decodeLaserScan(m.data, where).header.frame_id);
    } else {
      scan_frames.insert(ros2::decodeMultiEchoLaserScan(m.data, where).header.frame_id);
    }
  };
  bool first = true;
  bag->forEach({}, [&](const ros2::BagMessage& m) {
    const double t = 1e-9 * static_cast<double>(m.log_time_ns);
    if (first || t < s.t_first) s.t_first = t;
    if (first || t > s.t_last) s.t_last = t;
    first = false;
    ++s.messages;
    const std::string& name = m.topic->name;
    if (!readable.contains(name)) return true;
    const std::string where = path.string() + ": topic " + name + ", message " + std::to_string(counters[name]++);
    try {
      decode(m, where);
    } catch (const Error& e) {
      if (bad++ == 0) first_error = e.what();
    }
    return true;
  });
  for (const auto& [edge, n] : samples) s.transforms.push_back({edge.first, edge.second, statics[edge], n});
  s.scan_frames.assign(scan_frames.begin(), scan_frames.end());
  s.max_tilt = tf.maxTilt();
  s.notes = bag->notes();
  if (bad > 0) s.notes.push_back(std::to_string(bad) + " messages could not be decoded; the first: " + first_error);
  return s;
}

}  // namespace glassmap
