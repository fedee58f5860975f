// A ROS 2 bag's scans with laser poses from the transform tree (see ros2_log.hpp, log.hpp).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <optional>
#include <set>

#include "glassmap/core/angles.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/core/scan_spool.hpp"
#include "glassmap/io/ros2_cdr.hpp"
#include "glassmap/io/ros2_log.hpp"
#include "glassmap/io/ros2_tf.hpp"

namespace glassmap {

namespace fs = std::filesystem;
using ros2::BagTopic;

namespace {

constexpr double kTfToleranceS = 0.1;   // how far an odom -> base or base -> laser edge is held [s]
constexpr double kMapToleranceS = 1.0;  // map -> odom changes slowly: held this long [s]

bool isScanType(const std::string& t) { return t == ros2::kLaserScanType || t == ros2::kMultiEchoLaserScanType; }

std::string topicList(const std::vector<BagTopic>& topics) {
  std::string s;
  for (const BagTopic& t : topics) s += (s.empty() ? "" : ", ") + t.name + " (" + t.type + ")";
  return s.empty() ? "none" : s;
}

std::string names(const std::vector<const BagTopic*>& ts) {
  std::string s;
  for (const BagTopic* t : ts) s += (s.empty() ? "" : ", ") + t->name;
  return s;
}

/// The topic named `wanted`, else the only one of `candidates`; throws naming the choices.
const BagTopic* chooseTopic(const std::vector<BagTopic>& topics, const std::vector<const BagTopic*>& candidates,
                            const std::string& wanted, const char* what, const char* option, bool required,
                            const std::string& file) {
  if (!wanted.empty()) {
    for (const BagTopic& t : topics)
      if (t.name == wanted) return &t;
    throw Error(std::string("no topic ") + wanted + " (" + option + ") in the bag; its topics: " + topicList(topics),
                file);
  }
  if (candidates.size() == 1) return candidates.front();
  if (candidates.empty()) {
    if (!required) return nullptr;
    throw Error(std::string("no ") + what + " topic in the bag; its topics: " + topicList(topics), file);
  }
  throw Error(
      std::string("several ") + what + " topics in the bag (" + names(candidates) + "): choose one with " + option,
      file);
}

std::string seconds(double s) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3f", s);
  return b;
}

/// A scan as decoded, before its pose is known.
struct RawScan {
  LaserScan scan;
  std::size_t frame = 0;  // index into the frame names
};

template <class Msg>
void fillScanFields(const Msg& m, LaserScan& s, std::size_t beams, const std::string& where) {
  s.timestamp = m.header.stamp.seconds();
  s.start_angle = m.angle_min;
  s.angular_step = m.angle_increment;
  if (s.angular_step == 0.0 && beams > 1) s.angular_step = (double{m.angle_max} - m.angle_min) / double(beams - 1);
  s.max_range = m.range_max;
  if (!std::isfinite(s.start_angle) || !std::isfinite(s.angular_step))
    throw Error("scan angles are not finite", where, 0, "angle_min/angle_increment");
  if (!(s.max_range > 0.0) || !std::isfinite(s.max_range))
    throw Error("range_max " + std::to_string(m.range_max) + " is not a positive finite range", where, 0, "range_max");
  s.laser_id = 1;
  s.has_laser_pose = true;
}

/// REP 117 readings: NaN, inf, negative, absurd or below range_min -> no return; beyond
/// range_max kept (a max reading, as CARMEN logs have them).
float cleanRange(float r, float range_min, std::size_t& no_returns) {
  if (!std::isfinite(r) || r < 0.0f || r > kAbsurdRange || r < range_min) {
    ++no_returns;
    return kNoReturn;
  }
  return r;
}

}  // namespace

LaserLog readRos2Log(const fs::path& path, const LogReadOptions& options, LogReadNotes* notes_out) {
  const std::string file = path.string();
  const Ros2LogOptions& ro = options.ros2;
  const CarmenReadOptions& co = options.carmen;
  LogReadNotes notes;
  const auto bag = ros2::openBag(path);
  const std::vector<BagTopic>& topics = bag->topics();

  std::vector<const BagTopic*> scan_topics, odom_topics, tf_topics;
  for (const BagTopic& t : topics) {
    if (isScanType(t.type)) scan_topics.push_back(&t);
    if (t.type == ros2::kOdometryType) odom_topics.push_back(&t);
    if (t.type == ros2::kTFMessageType) tf_topics.push_back(&t);
  }
  const BagTopic* scan_topic =
      chooseTopic(topics, scan_topics, ro.scan_topic, "sensor_msgs/msg/LaserScan or MultiEchoLaserScan", "--scan-topic",
                  true, file);
  const BagTopic* odom_topic =
      chooseTopic(topics, odom_topics, ro.odom_topic, "nav_msgs/msg/Odometry", "--odom-topic", false, file);
  auto check = [&](const BagTopic* t) {
    try {
      ros2::checkTopicSchema(t->name, t->type, t->serialization_format, t->schema_encoding, t->schema_text);
    } catch (const Error& e) {
      throw Error(e.message(), file);
    }
  };
  check(scan_topic);
  if (odom_topic) check(odom_topic);
  if (!isScanType(scan_topic->type))
    throw Error("topic " + scan_topic->name + " (--scan-topic) has type " + scan_topic->type +
                    ", not sensor_msgs/msg/LaserScan or MultiEchoLaserScan",
                file);
  if (odom_topic && odom_topic->type != ros2::kOdometryType)
    throw Error(
        "topic " + odom_topic->name + " (--odom-topic) has type " + odom_topic->type + ", not nav_msgs/msg/Odometry",
        file);
  for (const BagTopic* t : tf_topics) check(t);
  const bool multi_echo = scan_topic->type == ros2::kMultiEchoLaserScanType;

  // one pass over the messages
  std::set<std::string> wanted{scan_topic->name};
  if (odom_topic) wanted.insert(odom_topic->name);
  for (const BagTopic* t : tf_topics) wanted.insert(t->name);
  ros2::TfBuffer tf(kTfToleranceS), odom_tf(kTfToleranceS);
  LaserLog log;
  std::vector<RawScan> raw;
  // A bag too large for memory (co.spool_directory): its scans on disk as read, their frames here.
  std::shared_ptr<ScanSpool> raw_spool;
  std::vector<std::uint32_t> raw_frames;
  std::vector<std::string> frames;
  std::string odom_parent, odom_child;
  std::size_t odom_frame_changes = 0;
  std::map<std::string, std::size_t> counters;
  std::size_t bytes = 0;
  bag->forEach(
      wanted,
      [&](const ros2::BagMessage& msg) {
        const std::string& topic = msg.topic->name;
        const std::size_t index = counters[topic]++;
        const std::string where = file + ": topic " + topic + ", message " + std::to_string(index);
        if (topic == scan_topic->name) {
          RawScan r;
          float range_min = 0.0f;
          std::string frame;
          if (multi_echo) {
            const auto m = ros2::decodeMultiEchoLaserScan(msg.data, where);
            fillScanFields(m, r.scan, m.ranges.size(), where);
            range_min = m.range_min;
            frame = m.header.frame_id;
            r.scan.ranges.reserve(m.ranges.size());
            for (const auto& echoes : m.ranges)  // no echo at all: no return
              r.scan.ranges.push_back(
                  cleanRange(echoes.empty() ? kNoReturn : echoes.front(), range_min, log.stats.no_return_ranges));
          } else {
            const auto m = ros2::decodeLaserScan(msg.data, where);
            fillScanFields(m, r.scan, m.ranges.size(), where);
            range_min = m.range_min;
            frame = m.header.frame_id;
            r.scan.ranges.resize(m.ranges.size());
            for (std::size_t i = 0; i < m.ranges.size(); ++i)
              r.scan.ranges[i] = cleanRange(m.ranges[i], range_min, log.stats.no_return_ranges);
          }
          const auto f = std::find(frames.begin(), frames.end(), frame);
          r.frame = static_cast<std::size_t>(f - frames.begin());
          if (f == frames.end()) frames.push_back(frame);
          bytes += r.scan.memoryBytes();
          if (!raw_spool && !co.spool_directory.empty() && bytes > co.spool_above_bytes) {
            raw_spool = std::make_shared<ScanSpool>(co.spool_directory);
            for (const RawScan& kept : raw) {
              raw_spool->append(kept.scan);
              raw_frames.push_back(static_cast<std::uint32_t>(kept.frame));
            }
            std::vector<RawScan>().swap(raw);
          }
          if (raw_spool) {
            raw_spool->append(r.scan);
            raw_frames.push_back(static_cast<std::uint32_t>(r.frame));
            return true;
          }
          if (co.max_memory_bytes > 0 && bytes > co.max_memory_bytes)
            throw Error("the log needs more than " + std::to_string(co.max_memory_bytes / 1000000) +
                            " MB in memory after " + std::to_string(raw.size()) + " scans (the memory limit)",
                        file);
          raw.push_back(std::move(r));
        } else if (odom_topic && topic == odom_topic->name) {
          const auto m = ros2::decodeOdometry(msg.data, where);
          StampedPose p;
          p.timestamp = m.header.stamp.seconds();
          p.pose = Pose2(m.position.x, m.position.y, ros2::quaternionYaw(m.orientation));
          p.tv = m.linear.x;
          p.rv = m.angular.z;
          if (!std::isfinite(p.pose.x()) || !std::isfinite(p.pose.y()) || !std::isfinite(p.pose.theta))
            throw Error("odometry pose is not finite", where, 0, "pose.pose");
          if (odom_parent.empty() && odom_child.empty()) {
            odom_parent = m.header.frame_id;
            odom_child = m.child_frame_id;
          } else if (odom_parent != m.header.frame_id || odom_child != m.child_frame_id) {
            ++odom_frame_changes;
          }
          odom_tf.add("odom", "base", p.timestamp, p.pose, false);
          log.odometry.push_back(p);
        } else {
          const bool is_static = topic.ends_with("tf_static");
          tf.add(ros2::decodeTFMessage(msg.data, where), is_static);
        }
        return true;
      },
      co.progress);
  std::stable_sort(log.odometry.begin(), log.odometry.end(),
                   [](const StampedPose& a, const StampedPose& b) { return a.timestamp < b.timestamp; });
  log.stats.odometry = log.odometry.size();

  const std::string scan_desc = scan_topic->name + " (" + scan_topic->type + ")";
  const std::size_t raw_count = raw_spool ? raw_spool->size() : raw.size();
  if (raw_count == 0) {
    if (co.require_scans) throw Error("no messages on the scan topic " + scan_desc, file);
    if (notes_out) *notes_out = notes;
    return log;
  }

  // frames
  const std::string& odom_frame = ro.odom_frame;
  std::string base = ro.base_frame;
  if (base.empty() && !odom_child.empty()) base = odom_child;
  if (base.empty()) {
    const auto kids = tf.dynamicChildren(odom_frame);
    base = kids.size() == 1 ? kids.front() : "base_link";
  }
  const bool odom_from_tf = tf.connected(odom_frame, base) && odom_frame != base;
  const bool odom_from_msgs = !odom_from_tf && !log.odometry.empty();
  const bool have_map = ro.map_frame != odom_frame && tf.connected(ro.map_frame, odom_frame);
  bool use_map = false;
  switch (ro.pose_source) {
    case BagPoseSource::Map:
      if (!have_map)
        throw Error("no " + ro.map_frame + " -> " + odom_frame + " transform in the bag (map poses requested; " +
                        "--map-frame/--odom-frame name the frames)",
                    file);
      use_map = true;
      break;
    case BagPoseSource::Auto:
      use_map = have_map;
      if (!have_map)
        notes.warnings.push_back("no " + ro.map_frame + " -> " + odom_frame +
                                 " transform in the bag: laser poses from odometry alone (not SLAM-corrected)");
      break;
    case BagPoseSource::Odometry:
      if (have_map) notes.notes.push_back(ro.map_frame + " -> " + odom_frame + " ignored: odometry poses requested");
      break;
  }
  if (!odom_from_tf && !odom_from_msgs)
    throw Error("no odometry: neither a " + odom_frame + " -> " + base + " transform nor " +
                    (odom_topic ? "messages on " + odom_topic->name : std::string("a nav_msgs/msg/Odometry topic")) +
                    " (--odom-frame, --base-frame, --odom-topic name them); topics: " + topicList(topics),
                file);
  if (odom_from_msgs && odom_frame_changes)
    notes.warnings.push_back(std::to_string(odom_frame_changes) + " odometry messages on " + odom_topic->name +
                             " name other frames than the first (" + odom_parent + " -> " + odom_child + ")");

  // per laser frame: base -> laser
  std::vector<bool> laser_connected(frames.size());
  for (std::size_t f = 0; f < frames.size(); ++f) {
    laser_connected[f] = frames[f].empty() || frames[f] == base || tf.connected(base, frames[f]);
    if (!laser_connected[f])
      notes.warnings.push_back("no " + base + " -> " + frames[f] +
                               " transform (/tf_static): the laser is taken to sit at " + base + " (identity)");
  }

  std::size_t no_odom = 0, no_map = 0, no_laser = 0;
  bool have_time = false;
  double last_time = 0.0;
  // The scan's poses from the transforms at its stamp; false (counted) when one is missing.
  auto place = [&](LaserScan& scan, std::size_t frame) {
    const double t = scan.timestamp;
    const auto T_odom_base = odom_from_tf ? tf.lookup(odom_frame, base, t) : odom_tf.lookup("odom", "base", t);
    if (!T_odom_base) {
      ++no_odom;
      return false;
    }
    Pose2 T_base_laser;
    if (laser_connected[frame] && !frames[frame].empty()) {
      const auto p = tf.lookup(base, frames[frame], t);
      if (!p) {
        ++no_laser;
        return false;
      }
      T_base_laser = *p;
    }
    Pose2 T_map_odom;
    if (use_map) {
      const auto p = tf.lookup(ro.map_frame, odom_frame, t, kMapToleranceS);
      if (!p) {
        ++no_map;
        return false;
      }
      T_map_odom = *p;
    }
    scan.odom_pose = *T_odom_base;
    scan.has_odom = true;
    scan.laser_pose = T_map_odom * *T_odom_base * T_base_laser;
    if (have_time) {
      if (t < last_time) ++log.stats.backward_timestamps;
      if (t == last_time) ++log.stats.repeated_timestamps;
    }
    have_time = true;
    last_time = t;
    return true;
  };
  if (raw_spool) {
    // Placed block by block from the raw spool into the log's own.
    raw_spool->flush();
    auto placed = std::make_shared<ScanSpool>(co.spool_directory);
    const std::size_t block = spoolBlockBytes(co.spool_above_bytes);
    raw_spool->forEachBlock(block, [&](std::vector<LaserScan>& scans, std::size_t first) {
      for (std::size_t i = 0; i < scans.size(); ++i)
        if (place(scans[i], raw_frames[first + i])) placed->append(scans[i]);
    });
    placed->flush();
    raw_spool.reset();
    std::vector<std::uint32_t>().swap(raw_frames);
    log.spooled = SpooledScans{placed, Vec2::Zero(), {}, block};
  } else {
    log.scans.reserve(raw.size());
    for (RawScan& r : raw)
      if (place(r.scan, r.frame)) log.scans.push_back(std::move(r.scan));
  }
  log.stats.scans = log.scanCount();

  // what was used
  std::string frame_names;
  for (const auto& f : frames) frame_names += (frame_names.empty() ? "" : ", ") + (f.empty() ? "\"\"" : f);
  notes.notes.push_back("scans from " + scan_desc + ", frame " + frame_names + ": " + std::to_string(raw_count) +
                        " messages" + (multi_echo ? " (first echo of each beam)" : ""));
  std::string chain = "laser poses from ";
  chain += use_map ? ro.map_frame + " -> " + odom_frame + " (/tf)" : odom_frame;
  chain += " -> " + base + (odom_from_tf ? " (/tf)" : " (" + odom_topic->name + " odometry messages)");
  for (std::size_t f = 0; f < frames.size(); ++f)
    if (!frames[f].empty() && frames[f] != base)
      chain += std::string(f ? "," : "") + " -> " + frames[f] + (laser_connected[f] ? " (tf)" : " (identity)");
  notes.notes.push_back(chain);
  auto skipped = [&](std::size_t n, const std::string& why) {
    if (n) notes.warnings.push_back(std::to_string(n) + " of " + std::to_string(raw_count) + " scans skipped: " + why);
  };
  skipped(no_odom, "no " + odom_frame + " -> " + base + " within " + seconds(kTfToleranceS) + " s of their stamp");
  skipped(no_laser, "no " + base + " -> laser transform within " + seconds(kTfToleranceS) + " s of their stamp");
  skipped(no_map,
          "no " + ro.map_frame + " -> " + odom_frame + " within " + seconds(kMapToleranceS) + " s of their stamp");
  if (tf.tilted() > 0) {
    char b[160];
    std::snprintf(b, sizeof b, "%zu transforms tilted more than 5 deg (largest %.1f deg): projected onto the plane",
                  tf.tilted(), rad2deg(tf.maxTilt()));
    notes.warnings.push_back(b);
  }
  if (tf.invalid() > 0)
    notes.warnings.push_back(std::to_string(tf.invalid()) +
                             " transforms skipped (zero quaternion, non-finite translation or empty frame name)");
  if (co.require_scans && log.scanCount() == 0) {
    std::string why;
    for (const auto& w : notes.warnings) why += "; " + w;
    throw Error("no scan on " + scan_desc + " has a pose" + why, file);
  }
  if (notes_out) *notes_out = std::move(notes);
  return log;
}

}  // namespace glassmap
