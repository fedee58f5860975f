#include "glassmap/io/log_summary.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

namespace glassmap {

namespace {

/// Adds records to a summary one by one (the same figures for a stream and a log in memory).
class Summarizer {
 public:
  explicit Summarizer(LogSummary& s) : s_(s) {}

  void scan(const LaserScan& scan) {
    const std::size_t n = scan.ranges.size();
    const double fov = scan.fieldOfView();
    if (s_.scans == 0) {
      s_.beams_min = s_.beams_max = n;
      s_.fov_min = s_.fov_max = fov;
      s_.step_min = s_.step_max = scan.angular_step;
      s_.max_range_min = s_.max_range_max = scan.max_range;
    }
    ++s_.scans;
    ++s_.scans_per_laser[scan.laser_id];
    s_.beams_min = std::min(s_.beams_min, n);
    s_.beams_max = std::max(s_.beams_max, n);
    s_.fov_min = std::min(s_.fov_min, fov);
    s_.fov_max = std::max(s_.fov_max, fov);
    s_.step_min = std::min(s_.step_min, scan.angular_step);
    s_.step_max = std::max(s_.step_max, scan.angular_step);
    s_.max_range_min = std::min(s_.max_range_min, scan.max_range);
    s_.max_range_max = std::max(s_.max_range_max, scan.max_range);
    for (std::size_t i = 0; i < n; ++i) codes_.add(scan.laser_id, scan.ranges[i], i);
    for (float r : scan.ranges) {
      if (!std::isfinite(r)) continue;
      if (r >= scan.max_range)
        ++s_.max_readings;
      else
        s_.longest_return = std::max(s_.longest_return, static_cast<double>(r));
    }
    stamp(scan.timestamp);
    if (last_scan_time_ && scan.timestamp < *last_scan_time_) ++s_.time_reversals;
    last_scan_time_ = scan.timestamp;
    if (scan.has_laser_pose) {
      if (!path_laser_) path_laser_ = scan.laser_id;
      if (scan.laser_id == *path_laser_) {
        s_.pose_bounds.extend(scan.laser_pose.t);
        if (last_laser_pose_) s_.distance += (scan.laser_pose.t - last_laser_pose_->t).norm();
        last_laser_pose_ = scan.laser_pose;
      }
    }
  }
  void odometry(const StampedPose& p) {
    stamp(p.timestamp);
    if (last_odom_) s_.odometry_distance += (p.pose.t - last_odom_->t).norm();
    last_odom_ = p.pose;
  }
  /// The scanner's no-return value, as readCarmenLog finds it (after s_.stats is set). Coded
  /// readings below the header's maximum were counted as returns: count them as the max readings
  /// readCarmenLog makes of them.
  void finish() {
    codes_.record(s_.stats);
    for (const auto& [id, n] : s_.scans_per_laser) {
      std::size_t coded = 0;
      const double code = codes_.code(id, &coded);
      if (code > 0.0 && code < s_.max_range_min) {
        s_.max_readings += coded;
        if (s_.longest_return >= code - 0.005) s_.longest_return = codes_.longestBelowCode(id);
      }
    }
  }
  void stamp(double t) {
    if (!any_time_) {
      s_.t_first = s_.t_last = t;
      any_time_ = true;
    }
    s_.t_first = std::min(s_.t_first, t);
    s_.t_last = std::max(s_.t_last, t);
  }

 private:
  LogSummary& s_;
  MaxRangeCodeFinder codes_;
  bool any_time_ = false;
  std::optional<int> path_laser_;  // the laser whose poses give the distance travelled
  std::optional<Pose2> last_laser_pose_, last_odom_;
  std::optional<double> last_scan_time_;
};

}  // namespace

LogSummary summarizeCarmenLog(const std::filesystem::path& path, const CarmenReadOptions& options) {
  LogSummary s;
  Summarizer sum(s);
  CarmenCallbacks cb;
  cb.on_scan = [&](LaserScan&& scan) { sum.scan(scan); };
  cb.on_odometry = [&](const StampedPose& p) { sum.odometry(p); };
  cb.on_true_pose = [&](const StampedPose& p) { sum.stamp(p.timestamp); };
  s.stats = forEachCarmenRecord(path, cb, options);
  sum.finish();
  return s;
}

LogSummary summarizeLog(const LaserLog& log) {
  LogSummary s;
  Summarizer sum(s);
  for (const LaserScan& scan : log.scans) sum.scan(scan);
  for (const StampedPose& p : log.odometry) sum.odometry(p);
  for (const StampedPose& p : log.true_poses) sum.stamp(p.timestamp);
  s.stats = log.stats;
  sum.finish();
  return s;
}

}  // namespace glassmap
