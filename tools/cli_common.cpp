#include "cli_common.hpp"

#include "glassmap/core/atomic_file.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/io/floorplan.hpp"
#include "glassmap/pipeline/reports.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace glassmap::cli {
namespace {

std::vector<std::pair<int, Register>>& registry() {
  static std::vector<std::pair<int, Register>> verbs;
  return verbs;
}

}  // namespace

Registrar::Registrar(int order, Register fn) { registry().emplace_back(order, std::move(fn)); }

void registerAll(CLI::App& app) {
  auto& verbs = registry();
  std::stable_sort(verbs.begin(), verbs.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (auto& [order, fn] : verbs) fn(app);
}

CLI::App& verb(CLI::App& app, const std::string& name, const std::string& description) {
  for (CLI::App* sub : app.get_subcommands({})) {
    if (sub->get_name() == name) return *sub;
  }
  CLI::App* sub = app.add_subcommand(name, description);
  sub->require_subcommand(1);
  return *sub;
}

VectorMap readPlan(const std::string& path, const std::string& units, const std::string& layers, bool quiet,
                   std::string* warning_out, bool clutter) {
  FloorplanUnits assumed;
  FloorplanReadReport report;
  FloorplanReadOptions read;
  read.units = &assumed;
  read.report = &report;
  read.clutter = clutter;
  if (!units.empty()) read.unit_in_metres = parseLengthUnit(units, "units");
  read.layer_rules = parseLayerRules(layers, "--layers");
  VectorMap map = readFloorplan(path, read);
  if (!quiet && (report.by_layer_names || !report.notes.empty() || !report.warnings.empty()))
    std::cerr << formatReadReport(report);
  const std::string warning = implausibleExtentWarning(map, assumed, path);
  if (warning_out != nullptr)
    *warning_out = warning;
  else if (!quiet && !warning.empty())
    std::cerr << "glassmap: warning: " << warning << "\n";
  return map;
}

void addUnitsOption(CLI::App& cmd, std::string& units) {
  cmd.add_option("--units", units,
                 "units of the floorplan's coordinates, overriding what the file declares (CRS units,\n"
                 "DXF $INSUNITS; GDAL's default DXF header says inches): m, cm, mm, in, ft, us-ft, ... or\n"
                 "metres per unit; default: the file's own, metres when it declares none");
}

void addLayersOption(CLI::App& cmd, std::string& layers) {
  cmd.add_option("--layers", layers,
                 "CAD layer rules tried before the built-in table (AIA/NCS A-WALL, A-GLAZ, A-DOOR, ...):\n"
                 "\"glass=A-GLAZ*,*WINDOW*;wall=A-WALL*;ignore=A-FURN*\" (case-insensitive globs, first\n"
                 "match wins); unknown layers are read as wall and named on stderr");
}

void writeJsonFile(const std::filesystem::path& path, const nlohmann::json& j) { pipeline::writeJsonFile(path, j); }

Pose2 parsePose(const std::string& text, const std::string& field) {
  std::stringstream ss(text);
  double v[3];
  char c1 = 0, c2 = 0;
  if (!(ss >> v[0] >> c1 >> v[1] >> c2 >> v[2]) || c1 != ',' || c2 != ',' || !ss.eof())
    throw Error("expected x,y,theta (metres, metres, radians), got '" + text + "'", {}, 0, field);
  return {v[0], v[1], v[2]};
}

bool stderrIsTerminal() { return ::isatty(STDERR_FILENO) == 1; }

std::size_t peakMemoryBytes() { return pipeline::peakMemoryBytes(); }

std::string scanFitSummary(const vector::ScanFitStats& s) {
  char line[160];
  std::snprintf(line, sizeof line,
                "%zu of %zu segments moved (mean %.3f m); returns within %.2f m of their segment %.1f%% -> %.1f%%",
                s.moved, s.segments, s.mean_shift, s.band, 100.0 * s.explained_before, 100.0 * s.explained_after);
  return line;
}

std::string scanClutterSummary(const vector::ScanClutterStats& s) {
  char line[260];
  std::snprintf(line, sizeof line,
                "%zu segments in place of %zu%s; returns under 8 m near a segment %.1f%% -> %.1f%% (walls and panes "
                "alone %.1f%%)",
                s.added, s.replaced,
                s.restored > 0 ? (", " + std::to_string(s.restored) + " of the cells' kept").c_str() : "",
                100.0 * s.explained_before, 100.0 * s.explained_after, 100.0 * s.explained_walls);
  return line;
}

std::string profileSummary(const SensorProfile& p) {
  char rel[48] = "";
  if (p.range_sigma_rel.value > 0)
    std::snprintf(rel, sizeof rel, " + %.2f%% of range", 100.0 * p.range_sigma_rel.value);
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "range sigma %.3f m%s, hit/short/max/rand %.2f/%.2f/%.2f/%.2f; glass lobe peak %.2f sigma %.1f deg "
                "floor %.3f, reflected lambda %.3f/deg floor %.2f",
                p.range_sigma_m.value, rel, p.w_hit.value, p.w_short.value, p.w_max.value, p.w_rand.value,
                p.direct_peak.value, p.direct_sigma_deg.value, p.direct_floor.value, p.normal_lambda_per_deg.value,
                p.normal_floor.value);
  return buf;
}

std::function<void(std::uint64_t, std::uint64_t)> readProgress(bool show) {
  if (!show) return {};
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  auto last = start - std::chrono::seconds(1);
  return [start, last](std::uint64_t done, std::uint64_t total) mutable {
    const auto now = Clock::now();
    const bool finished = done >= total;
    if (!finished && now - last < std::chrono::milliseconds(100)) return;
    last = now;
    const double seconds = std::chrono::duration<double>(now - start).count();
    const double mb = static_cast<double>(done) / 1e6, total_mb = static_cast<double>(total) / 1e6;
    const int digits = total_mb < 10 ? 1 : 0;
    std::fprintf(stderr, "\rreading  %5.1f%% (%.*f of %.*f MB, %.1f MB/s)", total > 0 ? 100.0 * mb / total_mb : 0.0,
                 digits, mb, digits, total_mb, seconds > 0 ? mb / seconds : 0.0);
    if (finished) std::fputc('\n', stderr);
  };
}

void addLogOptions(CLI::App& cmd, LogReadOptions& options) {
  Ros2LogOptions& r = options.ros2;
  const std::string group = "ROS 2 bag logs";
  cmd.add_option("--scan-topic", r.scan_topic,
                 "bags: topic of the scans (sensor_msgs/msg/LaserScan or MultiEchoLaserScan); default: the only one")
      ->group(group);
  cmd.add_option("--odom-topic", r.odom_topic,
                 "bags: nav_msgs/msg/Odometry topic, used when /tf has no odom -> base transform; default: the only "
                 "one")
      ->group(group);
  cmd.add_option("--map-frame", r.map_frame, "bags: frame of SLAM-corrected poses (map -> odom in /tf)")
      ->capture_default_str()
      ->group(group);
  cmd.add_option("--odom-frame", r.odom_frame, "bags: odometry frame")->capture_default_str()->group(group);
  cmd.add_option("--base-frame", r.base_frame,
                 "bags: robot frame; default: the odometry's child_frame_id, else the child of the odometry frame in "
                 "/tf, else base_link")
      ->group(group);
}

void printLogNotes(const LogReadNotes& notes, bool quiet) {
  if (!quiet)
    for (const std::string& n : notes.notes) std::cerr << "glassmap: " << n << "\n";
  for (const std::string& w : notes.warnings) std::cerr << "glassmap: warning: " << w << "\n";
}

LaserLog readLogReporting(const std::string& path, const LogReadOptions& options, bool quiet) {
  LogReadNotes notes;
  LaserLog log = readLog(path, options, &notes);
  printLogNotes(notes, quiet);
  return log;
}

}  // namespace glassmap::cli
