#pragma once
/// Runs MCL over a whole laser log: odometry from the scans (or ODOM records) only, never the
/// log's laser poses; one pose estimate (T_map_laser) per scan.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <vector>

#include "glassmap/core/laser_scan.hpp"
#include "glassmap/localize/particle_filter.hpp"
#include "glassmap/localize/self_calibration.hpp"

namespace glassmap::localize {

/// Options of a run over a log.
struct LocalizeOptions {
  FilterOptions filter;
  int beams = 15;                           ///< beams per scan, spread evenly (0 = all)
  std::optional<Pose2> init;                ///< initial T_map_laser; none = global localization
  double init_sigma_xy = 0.1;               ///< spread around init [m]
  double init_sigma_theta = deg2rad(5.0);   ///< [rad]
  double update_min_trans = 0.01;           ///< correct only after this much travel [m] ...
  double update_min_rot = deg2rad(1.0);     ///< ... or this much turning [rad]
  Pose2 T_base_laser;                       ///< laser mounting on the robot (odometry is of the base)
  SelfCalibrationOptions self_calibration;  ///< refits of the sensor model to the log (on by default)
  double converged_min_travel = 2.0;        ///< converged at the end only after staying so over this
                                            ///< much travel [m] (a cloud that collapsed on the last
                                            ///< scans is not yet an answer)
  double converged_after_jump = 5.0;        ///< ... and after a jump of the estimate to another
                                            ///< hypothesis only once the robot travelled this far
                                            ///< since [m] (a global start's anneal_min_travel)
};

/// What a run did.
struct LocalizeResult {
  std::vector<StampedPose> trajectory;   ///< T_map_laser per scan
  std::vector<double> spread;            ///< particle spread per scan: ParticleFilter::spread() [m]
  std::vector<std::size_t> particles;    ///< particle count per scan
  std::vector<std::uint8_t> corrected;   ///< per scan: 1 when it was a measurement update
  std::vector<std::size_t> relocalized;  ///< per scan: relocalizations so far
  std::vector<std::uint8_t> settled;     ///< per scan: 1 when the filter is converged (one tight
                                         ///< hypothesis holds the mass: ParticleFilter::converged())
                                         ///< from this scan to the end
  bool converged = false;                ///< the cloud ends as one tight mode: the estimate can be trusted
  double converged_at = -1.0;            ///< time from the log's start after which it stays so [s]; -1 never
  std::size_t scans = 0;                 ///< scans read
  std::size_t updates = 0;               ///< measurement updates (corrections)
  std::size_t resamplings = 0;
  std::size_t injected = 0;                      ///< random particles drawn in total (probes, injection)
  std::size_t relocalizations = 0;               ///< jumps of the estimate to another hypothesis (a probe won)
  std::size_t probes = 0;                        ///< recovery probes started
  std::size_t breaks = 0;                        ///< scans that contradicted the one before them placed by
                                                 ///< odometry (a kidnap or an odometry jump: ScanConsistency)
  std::vector<SelfCalibrationFit> calibrations;  ///< the sensor model's refits, in order
  sensor::SensorParams final_params;             ///< the model's parameters at the end
  double mean_particles = 0.0;                   ///< mean particle count over the updates
  double seconds = 0.0;                          ///< wall time of the filter [s]
  double seconds_per_update = 0.0;               ///< mean wall time of predict + correct [s]
  double log_duration = 0.0;                     ///< time spanned by the log [s]
  double realTimeFactor() const { return seconds > 0 ? log_duration / seconds : 0.0; }
};

/// Localizes every scan of `log` against the model's map; with options.self_calibration enabled
/// the model's parameters are refitted to the log on the way (setParams). Throws Error when the
/// log has no odometry for its scans.
LocalizeResult localizeLog(const LaserLog& log, sensor::SensorModel& model, const LocalizeOptions& options);

/// Writes the per-scan filter state as CSV (atomically): t [s], spread_m, particles, corrected,
/// relocalizations, one row per estimate of result.trajectory. Throws Error when it cannot write.
void writeSpreadCsv(const std::filesystem::path& path, const LocalizeResult& result);

}  // namespace glassmap::localize
