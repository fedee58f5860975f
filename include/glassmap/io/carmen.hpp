#pragma once
/// CARMEN laser logs (.clf, .log, optionally gzip-compressed): read whole, stream, write.
///
/// Read line types: ROBOTLASER1/2 (with or without num_remissions), FLASER, RLASER, RAWLASER1..4,
/// ODOM, TRUEPOS, PARAM. Other types (NEFF, SYNC, ...) are skipped and counted; '#' lines and
/// empty lines are comments. A malformed line of a known type throws Error naming file, line and
/// field. Compression is detected from the content (gzip magic), not from the extension.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

#include "glassmap/core/laser_scan.hpp"

namespace glassmap {

/// Options of the CARMEN readers.
struct CarmenReadOptions {
  int laser_id = 0;                   ///< keep only scans of this laser (1 front, 2 rear, n for RAWLASERn); 0 keeps all
  double flaser_max_range = 0.0;      ///< max range of FLASER/RLASER scans [m]; 0: PARAM robot_front_laser_max /
                                      ///< robot_rear_laser_max when the log has it, else 80 (CARMEN's own guess)
  bool detect_max_range_code = true;  ///< readCarmenLog finds the scanner's "no return" value in the data
                                      ///< and treats it as max range (markMaxRangeCode)
  bool require_scans = true;          ///< readCarmenLog throws Error when the log holds no scan (empty file included)
  std::size_t max_memory_bytes = 0;   ///< readCarmenLog throws Error, while reading, once the log in memory
                                      ///< passes this (see memoryBytes) [bytes]; 0: no limit
  /// When set, readCarmenLog (and readLog for bags) keeps the scans on disk in this folder (an unlinked temporary file,
  /// core/scan_spool.hpp) once those in memory pass spool_above_bytes, and max_memory_bytes no
  /// longer counts them: a log of any size is read in bounded memory. Empty: always in memory.
  std::filesystem::path spool_directory;
  std::size_t spool_above_bytes = 0;  ///< see spool_directory [bytes]; 0 with a folder: spool from the first scan
  /// Called every few thousand lines and once at the end with the bytes of the file (as on disk,
  /// compressed for .gz) read so far and its size; may be empty.
  std::function<void(std::uint64_t done, std::uint64_t total)> progress;
};

/// Callbacks of the streaming reader; any may be empty. A scan is handed over by rvalue: move from it.
struct CarmenCallbacks {
  std::function<void(LaserScan&&)> on_scan;
  std::function<void(const StampedPose&)> on_odometry;                              ///< ODOM lines
  std::function<void(const StampedPose&)> on_true_pose;                             ///< TRUEPOS lines (the true pose)
  std::function<void(const std::string& name, const std::string& value)> on_param;  ///< PARAM lines
};

/// Reads a whole CARMEN log (plain or gzip) into memory.
LaserLog readCarmenLog(const std::filesystem::path& path, const CarmenReadOptions& options = {});

/// Reads a CARMEN log record by record in bounded memory, calling back in file order.
/// Never throws for an empty log (require_scans is ignored); returns what it met.
LogReadStats forEachCarmenRecord(const std::filesystem::path& path, const CarmenCallbacks& callbacks,
                                 const CarmenReadOptions& options = {});

/// Writes a log: PARAM lines, then ROBOTLASER<laser_id> (no remissions' values, num_remissions 0),
/// ODOM and TRUEPOS lines merged in time order. Numbers are written in their shortest exact form,
/// so readCarmenLog gives back equal values; a no-return range is written as "inf". A scan without
/// odometry gets its laser pose in the robot pose fields. A path ending in ".gz" is gzip-compressed.
/// Written atomically (temporary file, then rename).
void writeCarmenLog(const std::filesystem::path& path, const LaserLog& log);

/// CARMEN's guess of the field of view for FLASER/RLASER lines from the beam count [rad]
/// (carmen_laser_guess_fov: 181/361 beams -> 180 deg, 180 -> 179, 360 -> 179.5, 401 -> 100, else 180).
double carmenGuessFov(int num_beams);
/// CARMEN's guess of the angle between beams [rad] (carmen_laser_guess_angle_increment:
/// 180/181 beams -> 1 deg, 360/361 -> 0.5 deg, 400/401 -> 0.25 deg, else fov / (n - 1)).
double carmenGuessAngleIncrement(int num_beams);

}  // namespace glassmap
