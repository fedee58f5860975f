// glassmap info: what a laser log holds (scans, beams, field of view, range, duration, path).
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "cli_common.hpp"
#include "glassmap/core/angles.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/io/log.hpp"
#include "glassmap/io/log_summary.hpp"
#include "glassmap/io/ros2_log.hpp"

namespace glassmap {
namespace {

struct InfoArgs {
  std::string log;
  bool json = false;
  CarmenReadOptions read;
  LogReadOptions log_read;  // bags
};

const char* storageName(ros2::BagStorage s) { return s == ros2::BagStorage::Mcap ? "mcap" : "sqlite3"; }

nlohmann::json bagJson(const Ros2BagSummary& b) {
  nlohmann::json j;
  j["storage"] = storageName(b.storage);
  j["files"] = nlohmann::json::array();
  for (const auto& f : b.files) j["files"].push_back(f.string());
  j["messages"] = b.messages;
  j["time_first_s"] = b.t_first;
  j["time_last_s"] = b.t_last;
  j["topics"] = nlohmann::json::array();
  for (const auto& t : b.topics)
    j["topics"].push_back(
        {{"name", t.name}, {"type", t.type}, {"serialization", t.serialization_format}, {"messages", t.message_count}});
  j["transforms"] = nlohmann::json::array();
  for (const auto& t : b.transforms)
    j["transforms"].push_back(
        {{"parent", t.parent}, {"child", t.child}, {"static", t.is_static}, {"samples", t.samples}});
  j["scan_frames"] = b.scan_frames;
  j["max_tilt_deg"] = rad2deg(b.max_tilt);
  j["notes"] = b.notes;
  return j;
}

void printBag(const Ros2BagSummary& b, const std::string& path) {
  std::printf("%-20s %s (ROS 2 bag, %s, %zu file%s)\n", "bag", path.c_str(), storageName(b.storage), b.files.size(),
              b.files.size() == 1 ? "" : "s");
  std::printf("%-20s %llu in %.1f s (%.3f .. %.3f)\n", "messages", static_cast<unsigned long long>(b.messages),
              b.duration(), b.t_first, b.t_last);
  std::printf("topics\n");
  for (const auto& t : b.topics)
    std::printf("  %-26s %-36s %8llu%s\n", t.name.c_str(), t.type.c_str(),
                static_cast<unsigned long long>(t.message_count),
                t.serialization_format == "cdr" ? "" : ("  (" + t.serialization_format + ")").c_str());
  std::printf("frames\n");
  for (const auto& t : b.transforms)
    std::printf("  %-26s -> %-24s %s %zu\n", t.parent.c_str(), t.child.c_str(), t.is_static ? "static " : "dynamic",
                t.samples);
  if (b.transforms.empty()) std::printf("  (no /tf or /tf_static transforms)\n");
  std::string frames;
  for (const auto& f : b.scan_frames) frames += (frames.empty() ? "" : ", ") + f;
  if (!frames.empty()) std::printf("%-20s %s\n", "scan frames", frames.c_str());
  if (b.max_tilt > 0.0872664626)
    std::printf("%-20s %.1f deg (projected onto the plane)\n", "largest tilt", rad2deg(b.max_tilt));
  for (const auto& n : b.notes) std::printf("%-20s %s\n", "note", n.c_str());
}

std::string range(double lo, double hi, const char* fmt) {
  char a[64], b[64];
  std::snprintf(a, sizeof a, fmt, lo);
  std::snprintf(b, sizeof b, fmt, hi);
  return lo == hi ? std::string(a) : std::string(a) + " .. " + b;
}

void run(const InfoArgs& args) {
  const auto t0 = std::chrono::steady_clock::now();
  const bool bag = isRos2Bag(args.log);
  std::optional<Ros2BagSummary> bag_summary;
  LogSummary s;
  std::string scan_error;  // a bag whose scans cannot be read is still summarised
  if (bag) {
    bag_summary = summarizeRos2Bag(args.log);
    if (!args.json) printBag(*bag_summary, args.log);
    std::fflush(stdout);  // before readLog's notes on stderr
    try {
      LogReadOptions read = args.log_read;
      read.carmen.progress = args.read.progress;
      read.ros2.pose_source = BagPoseSource::Auto;
      s = summarizeLog(cli::readLogReporting(args.log, read, args.json));
    } catch (const Error& e) {
      scan_error = e.what();
      std::cerr << "glassmap: warning: " << scan_error << "\n";
    }
  } else {
    s = summarizeCarmenLog(args.log, args.read);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  if (args.json) {
    nlohmann::json j;
    j["log"] = args.log;
    if (bag_summary) j["bag"] = bagJson(*bag_summary);
    if (!scan_error.empty()) j["scan_error"] = scan_error;
    j["scans"] = s.scans;
    nlohmann::json per_laser = nlohmann::json::object();
    for (const auto& [id, n] : s.scans_per_laser) per_laser[std::to_string(id)] = n;
    j["scans_per_laser"] = per_laser;
    j["beams_per_scan"] = {{"min", s.beams_min}, {"max", s.beams_max}};
    j["field_of_view_deg"] = {{"min", rad2deg(s.fov_min)}, {"max", rad2deg(s.fov_max)}};
    j["angular_resolution_deg"] = {{"min", rad2deg(s.step_min)}, {"max", rad2deg(s.step_max)}};
    j["max_range_m"] = {{"min", s.max_range_min}, {"max", s.max_range_max}};
    j["longest_return_m"] = s.longest_return;
    j["max_readings"] = s.max_readings;
    j["no_return_ranges"] = s.stats.no_return_ranges;
    if (s.stats.max_range_code > 0)
      j["max_range_code"] = {{"value_m", s.stats.max_range_code}, {"readings", s.stats.max_range_code_readings}};
    j["backward_timestamps"] = s.stats.backward_timestamps;
    j["repeated_timestamps"] = s.stats.repeated_timestamps;
    j["time_first_s"] = s.t_first;
    j["time_last_s"] = s.t_last;
    j["duration_s"] = s.duration();
    j["time_reversals"] = s.time_reversals;
    j["distance_travelled_m"] = s.distance;
    j["odometry_distance_m"] = s.odometry_distance;
    if (!s.pose_bounds.isEmpty()) {
      j["pose_bounds_m"] = {{"min", {s.pose_bounds.min().x(), s.pose_bounds.min().y()}},
                            {"max", {s.pose_bounds.max().x(), s.pose_bounds.max().y()}}};
    } else {
      j["pose_bounds_m"] = nullptr;
    }
    j["odometry_records"] = s.stats.odometry;
    j["true_pose_records"] = s.stats.true_poses;
    j["param_records"] = s.stats.params;
    j["lines"] = s.stats.lines;
    j["comment_lines"] = s.stats.comment_lines;
    j["skipped_lines"] = s.stats.skipped_by_type;
    j["filtered_scans"] = s.stats.filtered_scans;
    j["read_seconds"] = seconds;
    std::cout << j.dump(2) << "\n";
    return;
  }

  auto row = [](const char* key, const std::string& value) { std::printf("%-20s %s\n", key, value.c_str()); };
  char buf[256];
  if (bag && !scan_error.empty()) return;
  if (!bag) row("log", args.log);
  std::string scans = std::to_string(s.scans);
  if (s.scans_per_laser.size() > 1 || (s.scans_per_laser.size() == 1 && s.scans_per_laser.begin()->first != 1)) {
    scans += " (";
    for (const auto& [id, n] : s.scans_per_laser) {
      if (scans.back() != '(') scans += ", ";
      scans += "laser " + std::to_string(id) + ": " + std::to_string(n);
    }
    scans += ")";
  }
  row("scans", scans);
  if (s.scans > 0) {
    row("beams per scan", s.beams_min == s.beams_max
                              ? std::to_string(s.beams_min)
                              : std::to_string(s.beams_min) + " .. " + std::to_string(s.beams_max));
    row("field of view", range(rad2deg(s.fov_min), rad2deg(s.fov_max), "%.2f") + " deg");
    row("angular resolution", range(rad2deg(s.step_min), rad2deg(s.step_max), "%.3f") + " deg");
    std::snprintf(buf, sizeof buf, " m (longest return %.2f m, %zu max-range readings)", s.longest_return,
                  s.max_readings);
    row("max range", range(s.max_range_min, s.max_range_max, "%.2f") + buf);
  }
  std::snprintf(buf, sizeof buf, "%.1f s (%.3f .. %.3f)%s", s.duration(), s.t_first, s.t_last,
                s.time_reversals
                    ? (", " + std::to_string(s.time_reversals) + " scans stamped earlier than the one before").c_str()
                    : "");
  row("duration", buf);
  std::snprintf(buf, sizeof buf, "%.1f m (laser poses); odometry %.1f m", s.distance, s.odometry_distance);
  row("distance travelled", buf);
  if (!s.pose_bounds.isEmpty()) {
    const Vec2 size = s.pose_bounds.max() - s.pose_bounds.min();
    std::snprintf(buf, sizeof buf, "x %.2f .. %.2f m, y %.2f .. %.2f m (%.1f x %.1f m)", s.pose_bounds.min().x(),
                  s.pose_bounds.max().x(), s.pose_bounds.min().y(), s.pose_bounds.max().y(), size.x(), size.y());
    row("pose bounds", buf);
  }
  row("odometry records", std::to_string(s.stats.odometry));
  if (s.stats.true_poses) row("true poses", std::to_string(s.stats.true_poses));
  if (!bag) {
    row("params", std::to_string(s.stats.params));
    std::string skipped = s.stats.skipped_by_type.empty() ? "none" : "";
    for (const auto& [type, n] : s.stats.skipped_by_type) {
      if (!skipped.empty()) skipped += ", ";
      skipped += type + " " + std::to_string(n);
    }
    row("skipped lines", skipped);
  }
  row("no-return ranges", std::to_string(s.stats.no_return_ranges) + " (non-finite, negative or > 1e6 m)");
  if (s.stats.max_range_code > 0) {
    char code[160];
    std::snprintf(code, sizeof code, "%.3f m, %zu readings (read as max range: no return)", s.stats.max_range_code,
                  s.stats.max_range_code_readings);
    row("no-return code", code);
  }
  if (s.stats.backward_timestamps || s.stats.repeated_timestamps)
    row("scan timestamps", std::to_string(s.stats.backward_timestamps) + " going backwards, " +
                               std::to_string(s.stats.repeated_timestamps) + " repeated");
  if (s.stats.filtered_scans) row("filtered scans", std::to_string(s.stats.filtered_scans) + " (--laser)");
  if (bag)
    std::snprintf(buf, sizeof buf, "%llu messages in %.2f s", static_cast<unsigned long long>(bag_summary->messages),
                  seconds);
  else
    std::snprintf(buf, sizeof buf, "%zu lines in %.2f s", s.stats.lines, seconds);
  row("read", buf);
}

const cli::Registrar reg(10, [](CLI::App& app) {
  auto args = std::make_shared<InfoArgs>();
  CLI::App* sub = app.add_subcommand(
      "info",
      "Summarise a laser log, CARMEN (plain or gzip) or ROS 2 bag: scans, beams per scan, field of view, "
      "angular resolution, max range, duration, distance travelled, bounding box of the laser poses, odometry "
      "records, skipped line types and no-return ranges; for a bag first its topics (type, message count), "
      "the frames of /tf and /tf_static and its time span, then the scans as `map` reads them.");
  sub->add_option("log", args->log, cli::kLogHelp)->required()->check(CLI::ExistingPath);
  cli::addLogOptions(*sub, args->log_read);
  sub->add_flag("--json", args->json, "print the figures as JSON on stdout instead of a table");
  sub->add_option("--laser", args->read.laser_id,
                  "count only scans of this laser (1 = FLASER/front, 2 = RLASER/rear, n = RAWLASERn); 0 = all")
      ->capture_default_str();
  sub->add_option("--max-range", args->read.flaser_max_range,
                  "max range of FLASER/RLASER scans [m]; 0 = PARAM robot_front_laser_max, else 80 (CARMEN's guess)")
      ->capture_default_str();
  sub->callback([args] { run(*args); });
});

}  // namespace
}  // namespace glassmap
