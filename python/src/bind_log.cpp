// Laser logs: read_log (CARMEN logs and ROS 2 bags through glassmap::readLog), Log and Scan.
#include <cmath>
#include <limits>

#include "common.hpp"
#include "glassmap/core/error.hpp"

namespace glassmap::python {
namespace {

py::array_t<double> poseArray(const std::vector<StampedPose>& poses) {
  py::array_t<double> out({static_cast<py::ssize_t>(poses.size()), py::ssize_t{4}});
  auto a = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const auto r = static_cast<py::ssize_t>(i);
    a(r, 0) = poses[i].timestamp;
    a(r, 1) = poses[i].pose.x();
    a(r, 2) = poses[i].pose.y();
    a(r, 3) = poses[i].pose.theta;
  }
  return out;
}

py::dict statsDict(const LogReadStats& s) {
  py::dict d;
  d["lines"] = s.lines;
  d["scans"] = s.scans;
  d["skipped_lines"] = s.skipped_lines;
  d["skipped_by_type"] = s.skipped_by_type;
  d["comment_lines"] = s.comment_lines;
  d["no_return_ranges"] = s.no_return_ranges;
  d["backward_timestamps"] = s.backward_timestamps;
  d["repeated_timestamps"] = s.repeated_timestamps;
  d["odometry"] = s.odometry;
  d["true_poses"] = s.true_poses;
  d["params"] = s.params;
  d["filtered_scans"] = s.filtered_scans;
  return d;
}

std::size_t index(const Log& log, py::ssize_t i) {
  const auto n = static_cast<py::ssize_t>(log.log.scans.size());
  if (i < 0) i += n;
  if (i < 0 || i >= n) throw py::index_error("scan index out of range");
  return static_cast<std::size_t>(i);
}

}  // namespace

void bindLog(py::module_& m) {
  py::class_<LaserScan>(m, "Scan", "One 2D laser scan of a Log (a view: it keeps its Log alive).")
      .def_property_readonly(
          "ranges",
          [](py::object self) {
            LaserScan& s = self.cast<LaserScan&>();
            return py::array_t<float>(static_cast<py::ssize_t>(s.ranges.size()), s.ranges.data(), self);
          },
          "ranges [m] as a float32 numpy array (a view into the log; inf = no return, >= max_range = max reading)")
      .def_property_readonly(
          "angles",
          [](const LaserScan& s) {
            py::array_t<double> out(static_cast<py::ssize_t>(s.ranges.size()));
            auto a = out.mutable_unchecked<1>();
            for (std::size_t i = 0; i < s.ranges.size(); ++i) a(static_cast<py::ssize_t>(i)) = s.beamAngle(i);
            return out;
          },
          "beam angles in the laser frame [rad]")
      .def_readonly("angle_min", &LaserScan::start_angle, "angle of the first beam in the laser frame [rad]")
      .def_readonly("angle_increment", &LaserScan::angular_step, "angle between beams [rad]")
      .def_readonly("max_range", &LaserScan::max_range, "sensor maximum range [m]")
      .def_readonly("time", &LaserScan::timestamp, "timestamp [s]")
      .def_readonly("laser_id", &LaserScan::laser_id, "CARMEN laser number")
      .def_property_readonly(
          "pose", [](const LaserScan& s) { return poseTuple(s.laser_pose); },
          "laser pose (x, y, theta) in the map frame [m, m, rad], SLAM-corrected where the log has it")
      .def_property_readonly(
          "odom",
          [](const LaserScan& s) -> py::object {
            if (!s.has_odom) return py::none();
            return poseTuple(s.odom_pose);
          },
          "robot odometry pose (x, y, theta), or None when the scan has none")
      .def_readonly("has_laser_pose", &LaserScan::has_laser_pose)
      .def("__len__", [](const LaserScan& s) { return s.ranges.size(); })
      .def("__repr__", [](const LaserScan& s) {
        return "<glassmap.Scan t=" + std::to_string(s.timestamp) + " beams=" + std::to_string(s.ranges.size()) + ">";
      });

  py::class_<Log, std::shared_ptr<Log>>(m, "Log", "A laser log in memory (read_log).")
      .def("__len__", [](const Log& l) { return l.log.scans.size(); })
      .def(
          "__getitem__", [](Log& l, py::ssize_t i) -> LaserScan& { return l.log.scans[index(l, i)]; },
          py::return_value_policy::reference_internal)
      .def(
          "__iter__", [](Log& l) { return py::make_iterator(l.log.scans.begin(), l.log.scans.end()); },
          py::keep_alive<0, 1>())
      .def_property_readonly(
          "scans",
          [](py::object self) {
            Log& l = self.cast<Log&>();
            py::list out;
            for (LaserScan& s : l.log.scans)
              out.append(py::cast(&s, py::return_value_policy::reference_internal, self));
            return out;
          },
          "the scans, in log order (views into the log)")
      .def_readonly("path", &Log::path, "the file it was read from")
      .def_property_readonly(
          "times",
          [](const Log& l) {
            py::array_t<double> out(static_cast<py::ssize_t>(l.log.scans.size()));
            auto a = out.mutable_unchecked<1>();
            for (std::size_t i = 0; i < l.log.scans.size(); ++i)
              a(static_cast<py::ssize_t>(i)) = l.log.scans[i].timestamp;
            return out;
          },
          "scan timestamps [s] (N)")
      .def_property_readonly(
          "poses",
          [](const Log& l) {
            py::array_t<double> out({static_cast<py::ssize_t>(l.log.scans.size()), py::ssize_t{3}});
            auto a = out.mutable_unchecked<2>();
            for (std::size_t i = 0; i < l.log.scans.size(); ++i) {
              const Pose2& p = l.log.scans[i].laser_pose;
              const auto r = static_cast<py::ssize_t>(i);
              a(r, 0) = p.x();
              a(r, 1) = p.y();
              a(r, 2) = p.theta;
            }
            return out;
          },
          "laser poses of the scans (N x 3: x, y, theta)")
      .def_property_readonly(
          "odom_poses",
          [](const Log& l) {
            py::array_t<double> out({static_cast<py::ssize_t>(l.log.scans.size()), py::ssize_t{3}});
            auto a = out.mutable_unchecked<2>();
            const double nan = std::numeric_limits<double>::quiet_NaN();
            for (std::size_t i = 0; i < l.log.scans.size(); ++i) {
              const LaserScan& s = l.log.scans[i];
              const auto r = static_cast<py::ssize_t>(i);
              a(r, 0) = s.has_odom ? s.odom_pose.x() : nan;
              a(r, 1) = s.has_odom ? s.odom_pose.y() : nan;
              a(r, 2) = s.has_odom ? s.odom_pose.theta : nan;
            }
            return out;
          },
          "odometry poses of the scans (N x 3; NaN where a scan has none)")
      .def_property_readonly(
          "odometry", [](const Log& l) { return poseArray(l.log.odometry); }, "ODOM records (M x 4: t, x, y, theta)")
      .def_property_readonly(
          "true_poses", [](const Log& l) { return poseArray(l.log.true_poses); },
          "TRUEPOS records (K x 4: t, x, y, theta)")
      .def_property_readonly(
          "params", [](const Log& l) { return l.log.params; }, "PARAM name -> value")
      .def_property_readonly(
          "stats", [](const Log& l) { return statsDict(l.log.stats); }, "what the reader met")
      .def_property_readonly(
          "notes", [](const Log& l) { return l.notes.notes; }, "where the poses came from (bags)")
      .def_property_readonly(
          "warnings", [](const Log& l) { return l.notes.warnings; }, "doubtful assumptions of the reader (bags)")
      .def_property_readonly(
          "memory_bytes", [](const Log& l) { return l.log.memoryBytes(); }, "bytes the scans hold")
      .def("__repr__", [](const Log& l) {
        return "<glassmap.Log '" + l.path + "' scans=" + std::to_string(l.log.scans.size()) + ">";
      });

  m.def(
      "read_log",
      [](const py::object& path, const py::kwargs& kwargs) {
        const std::filesystem::path p = toPath(path, "read_log(path)");
        Options o("read_log", kwargs);
        LogReadOptions read;
        o.get("laser_id", read.carmen.laser_id);
        o.get("flaser_max_range", read.carmen.flaser_max_range);
        double max_memory_mb = 0.0;
        if (o.positive("max_memory", max_memory_mb))
          read.carmen.max_memory_bytes = static_cast<std::size_t>(max_memory_mb * 1e6);
        o.get("scan_topic", read.ros2.scan_topic);
        o.get("odom_topic", read.ros2.odom_topic);
        o.get("map_frame", read.ros2.map_frame);
        o.get("odom_frame", read.ros2.odom_frame);
        o.get("base_frame", read.ros2.base_frame);
        std::string source;
        if (o.get("pose_source", source)) {
          if (source == "auto")
            read.ros2.pose_source = BagPoseSource::Auto;
          else if (source == "map")
            read.ros2.pose_source = BagPoseSource::Map;
          else if (source == "odometry")
            read.ros2.pose_source = BagPoseSource::Odometry;
          else
            throw py::value_error("read_log(): option 'pose_source' must be auto, map or odometry, got '" + source +
                                  "'");
        }
        o.finish();
        auto log = std::make_shared<Log>();
        log->path = p.string();
        {
          py::gil_scoped_release release;
          log->log = readLog(p, read, &log->notes);
        }
        return log;
      },
      py::arg("path"),
      "Reads a laser log (CARMEN .clf/.log, plain or gzip; ROS 2 bags where glassmap reads them), as every\n"
      "glassmap verb does. Options: laser_id (keep one CARMEN laser, 0 = all), flaser_max_range [m],\n"
      "max_memory [MB] (stop once the log in memory passes it), and for bags scan_topic, odom_topic,\n"
      "map_frame, odom_frame, base_frame, pose_source ('auto', 'map', 'odometry').");
}

}  // namespace glassmap::python
