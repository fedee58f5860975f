#pragma once
/// A laser scan and a whole laser log: plain data, read and written by io/ (CARMEN logs).

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "glassmap/core/pose2.hpp"

namespace glassmap {

/// Range value meaning "no return" (non-finite, negative or absurd readings become this).
inline constexpr float kNoReturn = std::numeric_limits<float>::infinity();
/// Readings beyond this are absurd for any laser (and beyond a float's range, undefined to
/// convert): readers turn them into kNoReturn and count them as no-returns [m].
inline constexpr double kAbsurdRange = 1e6;

/// One 2D laser scan. Beam i points at start_angle + i * angular_step in the laser frame.
struct LaserScan {
  double timestamp = 0.0;      ///< [s]
  double start_angle = 0.0;    ///< angle of the first beam in the laser frame [rad]
  double angular_step = 0.0;   ///< angle between beams [rad]
  double max_range = 0.0;      ///< sensor maximum range [m]
  std::vector<float> ranges;   ///< [m]; kNoReturn for no return; >= max_range is a max reading
  Pose2 laser_pose;            ///< laser pose in the map frame, SLAM-corrected where the log has it
  Pose2 odom_pose;             ///< robot odometry pose (odometry frame)
  bool has_odom = false;       ///< odom_pose was present on the line
  bool has_laser_pose = true;  ///< laser_pose was present on the line (RAWLASERn lines have none)
  int laser_id = 1;            ///< CARMEN laser number (FLASER = 1, RLASER = 2, RAWLASERn = n)

  /// Angle of beam i in the laser frame [rad].
  double beamAngle(std::size_t i) const { return start_angle + static_cast<double>(i) * angular_step; }
  /// True when beam i is a real return (finite and below max range).
  bool isReturn(std::size_t i) const {
    const float r = ranges[i];
    return std::isfinite(r) && r < max_range;
  }
  /// Bytes the scan holds in memory (its record and its ranges) [bytes].
  std::size_t memoryBytes() const { return sizeof(LaserScan) + ranges.size() * sizeof(float); }
  /// Field of view covered by the beams [rad].
  double fieldOfView() const { return ranges.empty() ? 0.0 : static_cast<double>(ranges.size() - 1) * angular_step; }
};

/// A pose record with time (ODOM, TRUEPOS).
struct StampedPose {
  double timestamp = 0.0;  ///< [s]
  Pose2 pose;
  double tv = 0.0;  ///< translational velocity [m/s] (ODOM only)
  double rv = 0.0;  ///< rotational velocity [rad/s] (ODOM only)
};

/// What a reader met while reading.
struct LogReadStats {
  std::size_t lines = 0;                               ///< lines read
  std::size_t scans = 0;                               ///< scans kept
  std::size_t skipped_lines = 0;                       ///< lines of unknown type, skipped
  std::map<std::string, std::size_t> skipped_by_type;  ///< unknown line types and their counts
  std::size_t comment_lines = 0;                       ///< '#' and empty lines
  std::size_t no_return_ranges = 0;                    ///< non-finite, negative or absurd ranges turned into kNoReturn
  std::size_t backward_timestamps = 0;                 ///< kept scans whose timestamp is below the previous scan's
  std::size_t repeated_timestamps = 0;                 ///< kept scans whose timestamp equals the previous scan's
  std::size_t odometry = 0;                            ///< ODOM records
  std::size_t true_poses = 0;                          ///< TRUEPOS records
  std::size_t params = 0;                              ///< PARAM records
  std::size_t filtered_scans = 0;                      ///< scans dropped by a reader option (laser_id)
  double max_range_code = 0.0;                         ///< the scanner's "no return" value found in the data
                                                       ///< (see markMaxRangeCode) [m]; 0: none found
  std::size_t max_range_code_readings = 0;             ///< readings at that value
};

/// Scans a log does not hold in LaserLog::scans: kept on disk (ScanSpool, core/scan_spool.hpp), or
/// another log's scans lent block by block (borrowScans), read in order a block at a time.
class ScanStore {
 public:
  virtual ~ScanStore() = default;
  virtual std::size_t size() const = 0;                    ///< scans
  virtual std::uint64_t bytesOnDisk() const { return 0; }  ///< what the store keeps on disk [bytes]
  /// Calls f(block, first) for consecutive blocks of the scans, each holding about `block_bytes`
  /// of ranges (at least one scan); `first` is the index of the block's first scan. The block is
  /// the caller's copy.
  virtual void forEachBlock(std::size_t block_bytes,
                            const std::function<void(std::vector<LaserScan>& block, std::size_t first)>& f) const = 0;
};

/// The scans of `scans` as a store: each block copied out of them when read (so that a change,
/// a re-centred frame, can be applied to the copy). `scans` must outlive the store.
std::shared_ptr<const ScanStore> borrowScans(const std::vector<LaserScan>& scans);

/// Scans read through a store, and what every pass applies to a scan as it reads one: the very
/// changes a log in memory gets in place.
struct SpooledScans {
  std::shared_ptr<const ScanStore> spool;
  Vec2 shift = Vec2::Zero();              ///< subtracted from every laser pose (a re-centred frame) [m]
  std::map<int, double> max_range_codes;  ///< laser_id -> its no-return code (applyMaxRangeCode) [m]
  std::size_t block_bytes = 32u << 20;    ///< ranges read back per block [bytes]
};

/// A whole log: its scans in memory, or read through a store (a log larger than the memory budget
/// kept on disk, see CarmenReadOptions::spool_directory; a log re-centred block by block). Code that
/// reads every scan goes through forEachScanBlock, which serves both.
struct LaserLog {
  /// Bytes the log holds in memory (ranges and per-scan records; what a mapping run keeps;
  /// spooled scans: the block a pass reads back and its copy) [bytes].
  std::size_t memoryBytes() const {
    std::size_t b = (odometry.size() + true_poses.size()) * sizeof(StampedPose);
    for (const LaserScan& s : scans) b += s.memoryBytes();
    if (spooled) b += 2 * spooled->block_bytes;
    return b;
  }
  /// Scans in the log, in memory or in the store.
  std::size_t scanCount() const;
  std::vector<LaserScan> scans;               ///< the scans in memory (empty with a store)
  std::optional<SpooledScans> spooled;        ///< set when the scans are read through a store
  std::vector<StampedPose> odometry;          ///< ODOM lines
  std::vector<StampedPose> true_poses;        ///< TRUEPOS lines
  std::map<std::string, std::string> params;  ///< PARAM name -> value
  LogReadStats stats;
};

/// Many scanners report "no return" as one fixed value (a SICK LMS in CARMEN logs: 81.83 or
/// 81.91 m, or the 50 m a driver was configured with) while the log's header says another maximum
/// (CARMEN's FLASER lines carry none; readers guess 80 m). In the data that value is a spike at the
/// very top of the readings. When the largest finite reading of a laser (by laser_id) is shared,
/// within 5 mm, by at least 0.1% of its readings (and 5 readings, at 8 beam indices or more: a
/// far corner that a standing robot reads again and again is not a code), it is the max-range
/// code and stats records it; when it lies below a scan's max_range (or that is unset), the scan
/// gets max_range = code - 5 mm, so those readings count as max readings (isReturn false). Returns whether a
/// code was found. A log whose top readings are spread out is left as it is.
bool markMaxRangeCode(LaserLog& log);

class MaxRangeCodeFinder;
/// markMaxRangeCode with the readings already counted (by a reader, as it read them): applies
/// the codes `finder` found to the log's scans (spooled scans: as they are read back).
bool applyMaxRangeCodes(LaserLog& log, const MaxRangeCodeFinder& finder);

/// What markMaxRangeCode does to one scan of a laser whose code is `code` [m].
void applyMaxRangeCode(LaserScan& scan, double code);

/// Calls f(block, first) over the log's scans in log order: the scans in memory as one block, or
/// the spooled scans block by block, each as the log in memory would hold it (shift and no-return
/// code applied); `first` is the index of the block's first scan.
void forEachScanBlock(const LaserLog& log,
                      const std::function<void(std::span<const LaserScan> block, std::size_t first)>& f);

/// The counting behind markMaxRangeCode in one streaming pass (for readers that keep no scans):
/// add every reading, then ask for the code.
class MaxRangeCodeFinder {
 public:
  void add(int laser_id, float range, std::size_t beam);
  /// The code of `laser_id` (0 when its top readings are no spike) and its readings.
  double code(int laser_id, std::size_t* readings = nullptr) const;
  /// The longest reading of `laser_id` below its top readings [m].
  double longestBelowCode(int laser_id) const;
  /// The largest code over all lasers into stats (max_range_code, max_range_code_readings).
  void record(LogReadStats& stats) const;
  /// Every laser's code, for the lasers that have one.
  std::map<int, double> codes() const;

 private:
  struct Laser {
    double top = 0.0, below = 0.0;
    std::size_t readings = 0, at_top = 0;
    std::vector<bool> beams;  // beam indices the top value was read at (up to 8 counted)
    std::size_t distinct_beams = 0;
  };
  static void mark(Laser& l, std::size_t beam);
  std::map<int, Laser> lasers_;
};

}  // namespace glassmap
