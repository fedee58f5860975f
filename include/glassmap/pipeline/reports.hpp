#pragma once
/// What a pipeline run reports, as the command line and the Python module both give it: the
/// stats.json of a map run, the summary of a localization run, the fit of a calibration, the
/// sensor profile as JSON. One home, so `glassmap map` and `glassmap.map_log` report the same.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "glassmap/core/sensor_profile.hpp"
#include "glassmap/pipeline/localize_log.hpp"
#include "glassmap/pipeline/map_log.hpp"

namespace glassmap::pipeline {

/// Writes `j` (indented by 2, newline-terminated) to `path` atomically; throws Error on failure.
void writeJsonFile(const std::filesystem::path& path, const nlohmann::json& j);

/// The profile as JSON: {"range_sigma_m": v, "range_sigma_m_se": se, ..., "fitted": [...],
/// "source": ..., "wall_beams": n, "glass_beams": n}.
nlohmann::json profileJson(const SensorProfile& p);

/// A profile from JSON as profileJson writes it (any subset of its keys; the others keep their
/// defaults; "fitted" lists the keys estimated). Throws Error naming the key for a value of the
/// wrong type or a key that is neither a profile key nor in `ignored`.
SensorProfile profileFromJson(const nlohmann::json& j, const std::vector<std::string>& ignored = {});

/// The mapping options of a run as stats.json lists them ("options").
nlohmann::json mapOptionsJson(const MapOptions& options);

/// What a map run adds to its MapResult for stats.json.
struct MapRunInfo {
  std::string log;             ///< the log as named by the caller
  double seconds_read = 0.0;   ///< reading the log [s]
  double seconds_total = 0.0;  ///< the whole run, reading and writing included [s]
  std::size_t peak_memory_bytes = 0;
  std::uint64_t log_on_disk_bytes = 0;  ///< the log's scans kept on disk (logOnDiskBytes; 0: in memory)
  std::vector<std::string> files;       ///< file names written (none: no "files" key)
};

/// Bytes of the log's scans kept on disk (a log too large for memory, core/scan_spool.hpp); 0 when
/// they are in memory.
std::uint64_t logOnDiskBytes(const LaserLog& log);

/// stats.json of a map run (`glassmap map`): grid, counts, times, sensor profile, MRF, mirror
/// phantoms, pane fit, segments, options and files.
nlohmann::json mapStatsJson(const MapResult& result, const MapOptions& options, const MapRunInfo& run);

/// The grid's share of a memory budget: what the log in memory leaves of `budget_bytes`
/// (at least 1 byte, so an exhausted budget refuses any grid) [bytes].
std::size_t gridMemoryBudget(std::size_t budget_bytes, const LaserLog& log);

/// Peak resident memory of this process [bytes].
std::size_t peakMemoryBytes();

/// A sensor model's parameters as JSON (mixture weights normalised).
nlohmann::json sensorParamsJson(const sensor::SensorParams& params);

/// What the walls' fit to the returns did (vector::fitToScans), as `stats.json` and `vectorize
/// --json` write it.
nlohmann::json scanFitJson(const vector::ScanFitStats& stats);

/// What the clutter layer chosen from the returns is (vector::clutterFromScans), as `stats.json`
/// and `vectorize --json` write it.
nlohmann::json scanClutterJson(const vector::ScanClutterStats& stats);

/// The summary of a localization run (`glassmap localize --json`).
nlohmann::json localizeSummaryJson(const LocalizeResult& result, const LocalizeOptions& options);

/// The source a calibrated profile records: "calibrated from LOG against its own map" or
/// "... against PLAN" (file names only).
std::string calibrationSource(const std::string& log_path, const std::string& plan_path);

/// The fit of a calibration (`glassmap calibrate --json`): the profile (profileJson) plus the
/// log and floorplan names (plan_path "" = the log's own map: null), the alignment figures, the
/// per-angle table, warnings and the run's time.
nlohmann::json calibrationJson(const SensorProfile& profile, const CalibrateLogResult& result,
                               const std::string& log_path, const std::string& plan_path, double seconds);

}  // namespace glassmap::pipeline
