#pragma once
/// Whether consecutive laser scans agree with the odometry between them, whatever the map says.
///
/// A robot carried elsewhere (kidnapped), or odometry that jumped, shows as a scan that contradicts
/// the one before it once both are placed by odometry: readings end where the other scan saw free
/// space. A robot in clutter the map lacks does not: its scans still agree with each other. The
/// particle filter lets a recovery probe replace a tracked estimate only after such a break (or
/// after the tracked estimate has explained the scans badly for long: ParticleFilter).
///
/// The test is the free-space consistency of two range scans (the visibility test of scan
/// matching): a reading of one scan at distance d along a bearing of the other contradicts it when
/// every beam of the other within the bearing tolerance returned from farther than d + margin.
/// Both directions are counted; readings without a return (max range: glass, far away) say nothing.

#include <cstddef>
#include <optional>

#include "glassmap/core/pose2.hpp"
#include "glassmap/sensor/sensor_model.hpp"

namespace glassmap::localize {

/// Options of the test.
struct ScanConsistencyOptions {
  double margin = 0.15;                     ///< a reading contradicts only this far inside the free space [m] ...
  double margin_per_m = 0.05;               ///< ... plus this fraction of its range (odometry error) [-]
  double bearing_tolerance = deg2rad(1.5);  ///< the other scan's beams this close in bearing are compared
                                            ///< (at least half its beam spacing) [rad]
  double break_share = 0.3;                 ///< a break: more than this share of the compared readings
                                            ///< contradict the scan before [-]
  std::size_t min_compared = 8;             ///< fewer compared readings tell nothing [-]
};

/// One comparison of a scan with the scan before it.
struct ScanConsistencyResult {
  std::size_t compared = 0;      ///< readings compared (both directions) [-]
  std::size_t contradicted = 0;  ///< of them, inside the other scan's free space [-]
  double share = 0.0;            ///< contradicted / compared; 0 when too few were compared [-]
  bool broke = false;            ///< share above break_share with enough readings compared
};

/// Free-space contradictions of scan `b` taken at T_odom_b against scan `a` at T_odom_a, both
/// ways (poses of the laser in the odometry frame).
ScanConsistencyResult compareScans(const sensor::BeamSet& a, const Pose2& T_odom_a, const sensor::BeamSet& b,
                                   const Pose2& T_odom_b, const ScanConsistencyOptions& options);

/// Keeps the last scan and compares each new one with it.
class ScanConsistency {
 public:
  explicit ScanConsistency(ScanConsistencyOptions options = {}) : opt_(options) {}
  /// Compares `scan` at odometry pose T_odom_laser with the last scan given, then keeps it (the
  /// first scan compares with nothing: a result without readings).
  ScanConsistencyResult add(const sensor::BeamSet& scan, const Pose2& T_odom_laser);
  /// Forgets the last scan.
  void reset() { last_.reset(); }
  const ScanConsistencyOptions& options() const { return opt_; }

 private:
  ScanConsistencyOptions opt_;
  std::optional<sensor::BeamSet> last_;
  Pose2 last_pose_;
};

}  // namespace glassmap::localize
