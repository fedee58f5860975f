#pragma once
/// Shared plumbing of the glassmap command: verb registration, output helpers.

#include <CLI/CLI.hpp>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "glassmap/core/pose2.hpp"
#include "glassmap/core/sensor_profile.hpp"
#include "glassmap/geometry/vector_map.hpp"
#include "glassmap/io/log.hpp"
#include "glassmap/vector/scan_clutter.hpp"
#include "glassmap/vector/scan_fit.hpp"

namespace glassmap::cli {

/// A verb adds its subcommand to the app. `order` sorts verbs in --help.
using Register = std::function<void(CLI::App& app)>;

/// Registers a verb at static initialisation; use one per cmd_<verb>.cpp:
///   static const cli::Registrar reg(20, [](CLI::App& app) { ... });
struct Registrar {
  Registrar(int order, Register fn);
};

/// Calls every registered verb's Register in order.
void registerAll(CLI::App& app);

/// The subcommand `name` of app, created with `description` if it does not exist yet.
/// Lets several cmd_*.cpp files add sub-verbs to one verb (eval cells, eval traj, ...).
CLI::App& verb(CLI::App& app, const std::string& name, const std::string& description);

/// Writes `j` (indented, newline-terminated) to `path` atomically; throws Error on failure
/// (pipeline::writeJsonFile).
void writeJsonFile(const std::filesystem::path& path, const nlohmann::json& j);

/// Reads a floorplan with `units` ("" = the file's own; else a parseLengthUnit name or number) and
/// `layers` (--layers rules, "" = the built-in layer table only). Unless `quiet`, says on stderr
/// what was read as what when materials came from layer names (per layer: features, segments,
/// material or why ignored), with its notes and warnings, and warns when the plan's extent is
/// implausible for a building (naming the units read and --units); with `warning` given, that
/// extent warning (empty when none) goes there instead of stderr. `clutter`: read the CLUTTER layer
/// of our plans as walls too (FloorplanReadOptions::clutter).
VectorMap readPlan(const std::string& path, const std::string& units, const std::string& layers, bool quiet = false,
                   std::string* warning = nullptr, bool clutter = true);

/// Adds --units to a verb that reads floorplans (help text shared).
void addUnitsOption(CLI::App& cmd, std::string& units);

/// Adds --layers (CAD layer -> material rules) to a verb that reads floorplans.
void addLayersOption(CLI::App& cmd, std::string& layers);

/// Adds the options of a log that is a ROS 2 bag (--scan-topic, --odom-topic, --map-frame,
/// --odom-frame, --base-frame) to a verb that reads a log.
void addLogOptions(CLI::App& cmd, LogReadOptions& options);

/// What a log argument's help says: CARMEN logs and ROS 2 bags.
inline constexpr const char* kLogHelp =
    "laser log: CARMEN (.clf/.log, optionally .gz) or ROS 2 bag (rosbag2 folder, .mcap or .db3)";

/// Reads a log through readLog and prints its notes (unless `quiet`) and warnings on stderr.
LaserLog readLogReporting(const std::string& path, const LogReadOptions& options, bool quiet = false);

/// Prints readLog's notes (unless `quiet`) and warnings on stderr.
void printLogNotes(const LogReadNotes& notes, bool quiet);

/// Parses "x,y,theta" [m, m, rad]; throws Error naming `field` otherwise.
Pose2 parsePose(const std::string& text, const std::string& field);

/// One line for a summary: "range sigma 0.012 m, glass lobe peak 0.90 sigma 2.1 deg floor 0.000, ...".
std::string profileSummary(const SensorProfile& p);

/// One line for a summary: "60 of 166 segments moved (mean 0.041 m); returns within 0.05 m of their
/// segment 73.7% -> 78.7%".
std::string scanFitSummary(const vector::ScanFitStats& s);
/// One line on the clutter layer chosen from the returns.
std::string scanClutterSummary(const vector::ScanClutterStats& s);

/// Makes a CarmenReadOptions::progress that prints "reading  45.0% (120 of 270 MB, 35 MB/s)" on
/// stderr, overwriting itself, at most ten times a second; empty when `show` is false.
std::function<void(std::uint64_t, std::uint64_t)> readProgress(bool show);

/// True when stderr is a terminal (progress is shown only then).
bool stderrIsTerminal();

/// Peak resident memory of this process [bytes] (pipeline::peakMemoryBytes).
std::size_t peakMemoryBytes();

}  // namespace glassmap::cli
