#include "glassmap/io/log_summary.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

namespace glassmap {

LogSummary summarizeCarmenLog(const std::filesystem::path& path, const CarmenReadOptions& options) {
  LogSummary s;
  bool any_time = false;
  auto stamp = [&](double t) {
    if (!any_time) {
      s.t_first = s.t_last = t;
      any_time = true;
    }
    s.t_first = std::min(s.t_first, t);
    s.t_last = std::max(s.t_last, t);
  };
  std::optional<int> path_laser;  // the laser whose poses give the distance travelled
  std::optional<Pose2> last_laser_pose, last_odom;
  std::optional<double> last_scan_time;

  MaxRangeCodeFinder codes;  // the scanner's no-return value, as readCarmenLog finds it
  CarmenCallbacks cb;
  cb.on_scan = [&](LaserScan&& scan) {
    const std::size_t n = scan.ranges.size();
    const double fov = scan.fieldOfView();
    if (s.scans == 0) {
      s.beams_min = s.beams_max = n;
      s.fov_min = s.fov_max = fov;
      s.step_min = s.step_max = scan.angular_step;
      s.max_range_min = s.max_range_max = scan.max_range;
    }
    ++s.scans;
    ++s.scans_per_laser[scan.laser_id];
    s.beams_min = std::min(s.beams_min, n);
    s.beams_max = std::max(s.beams_max, n);
    s.fov_min = std::min(s.fov_min, fov);
    s.fov_max = std::max(s.fov_max, fov);
    s.step_min = std::min(s.step_min, scan.angular_step);
    s.step_max = std::max(s.step_max, scan.angular_step);
    s.max_range_min = std::min(s.max_range_min, scan.max_range);
    s.max_range_max = std::max(s.max_range_max, scan.max_range);
    for (std::size_t i = 0; i < n; ++i) codes.add(scan.laser_id, scan.ranges[i], i);
    for (float r : scan.ranges) {
      if (!std::isfinite(r)) continue;
      if (r >= scan.max_range)
        ++s.max_readings;
      else
        s.longest_return = std::max(s.longest_return, static_cast<double>(r));
    }
    stamp(scan.timestamp);
    if (last_scan_time && scan.timestamp < *last_scan_time) ++s.time_reversals;
    last_scan_time = scan.timestamp;
    if (scan.has_laser_pose) {
      if (!path_laser) path_laser = scan.laser_id;
      if (scan.laser_id == *path_laser) {
        s.pose_bounds.extend(scan.laser_pose.t);
        if (last_laser_pose) s.distance += (scan.laser_pose.t - last_laser_pose->t).norm();
        last_laser_pose = scan.laser_pose;
      }
    }
  };
  cb.on_odometry = [&](const StampedPose& p) {
    stamp(p.timestamp);
    if (last_odom) s.odometry_distance += (p.pose.t - last_odom->t).norm();
    last_odom = p.pose;
  };
  cb.on_true_pose = [&](const StampedPose& p) { stamp(p.timestamp); };
  s.stats = forEachCarmenRecord(path, cb, options);
  codes.record(s.stats);
  // Coded readings below the header's maximum were counted as returns above: count them as the
  // max readings readCarmenLog makes of them.
  for (const auto& [id, n] : s.scans_per_laser) {
    std::size_t coded = 0;
    const double code = codes.code(id, &coded);
    if (code > 0.0 && code < s.max_range_min) {
      s.max_readings += coded;
      if (s.longest_return >= code - 0.005) s.longest_return = codes.longestBelowCode(id);
    }
  }
  return s;
}

}  // namespace glassmap
