#pragma once
/// Self-calibration while localizing: the sensor model's range noise, mixture weights (how many
/// readings are short, missed or random: clutter and people a floorplan leaves out) and glass
/// response (direct-return lobe, reflections, offset through panes) fitted to the log itself, at
/// the poses the filter trusts, with sensor::calibrate (EM over the beam mixture, binomial fits
/// of the glass lobes; each scan's pose aligned to the walls first). A real laser's noise and a
/// real floor's clutter are not what any default assumes; without a sensor profile the filter
/// starts from the defaults and refits them as trusted scans accumulate (after 1 m of trusted
/// travel, then each time the trusted travel has tripled), so a run costs a few fits.
///
/// The odometry's noise is fitted too: over windows of about a metre between trusted estimates,
/// the estimated motion against the odometry's; the random walks of the motion model are raised
/// to what the windows show (never lowered below the defaults: the filter must cover the
/// odometry's error, and an estimate's own error is part of the residual).

#include <cstddef>
#include <vector>

#include "glassmap/core/laser_scan.hpp"
#include "glassmap/geometry/vector_map.hpp"
#include "glassmap/localize/motion_model.hpp"
#include "glassmap/sensor/sensor_model.hpp"

namespace glassmap::localize {

/// When and from what the model is refitted.
struct SelfCalibrationOptions {
  bool enabled = true;           ///< false: the model keeps its parameters
  double first_after_m = 1.0;    ///< first fit once the trusted scans span this much travel [m]
  double growth = 3.0;           ///< each later fit once the trusted travel grew by this factor [-]
  std::size_t max_scans = 400;   ///< scans per fit, spread evenly over the trusted ones
  double trust_spread = 0.2;     ///< a scan counts only while the particle spread is under this [m]
  double min_sigma_hit = 0.01;   ///< the fitted range noise is floored here [m]: pose error and the
                                 ///< plan's drawing error never vanish
  double max_sigma_hit = 0.25;   ///< ... and capped here [m]: wider is a lost filter, not noise
  double min_hit_weight = 0.3;   ///< a fit whose hit weight is below this is not applied [-]: a
                                 ///< filter that trusted a wrong pose sees mostly "clutter"
  bool motion = true;            ///< also fit the odometry's random walks
  double motion_window_m = 1.0;  ///< length of the windows compared [m]
  std::size_t min_windows = 10;  ///< fewer windows: the motion model is kept
};

/// One refit.
struct SelfCalibrationFit {
  double time = 0.0;               ///< log time of the fit, from the log's start [s]
  std::size_t scans = 0;           ///< trusted scans it used
  double trusted_m = 0.0;          ///< trusted travel so far [m]
  bool applied = false;            ///< false: rejected (see min_hit_weight), the model kept its parameters
  sensor::SensorParams params;     ///< the parameters fitted (applied or not)
  std::size_t motion_windows = 0;  ///< windows the motion fit used (0: no fit)
  OdometryNoise noise;             ///< the motion model after the fit
};

/// Collects trusted scans and refits the parameters on schedule.
class SelfCalibrator {
 public:
  SelfCalibrator(const VectorMap& map, SelfCalibrationOptions options);
  /// Notes scan `index` of the log with its estimate, the particle spread about it [m] and the
  /// laser odometry pose, trusted over a step of `step_m` [m]; `update` counts the filter's updates
  /// (consecutive numbers: no gap).
  void add(std::size_t index, const Pose2& estimate, double spread, const Pose2& odometry, double step_m,
           std::size_t update);
  /// True when the trusted travel reached the next fit.
  bool due() const;
  /// Fits on the trusted scans of `log` (the one the indices refer to), starting from `current`
  /// (values the data cannot tell keep it), and schedules the next fit.
  SelfCalibrationFit fit(const LaserLog& log, const sensor::SensorParams& current, const OdometryNoise& noise);

 private:
  std::size_t fitMotion(OdometryNoise& noise) const;
  const VectorMap& map_;
  SelfCalibrationOptions opt_;
  std::vector<std::size_t> scans_, updates_;
  std::vector<Pose2> poses_, odometry_;
  std::vector<double> along_;   // trusted travel at each entry [m]
  std::vector<double> spread_;  // particle spread at each entry [m]
  double trusted_m_ = 0.0;
  double next_fit_m_ = 0.0;
};

/// The profile a model's parameters amount to: the inverse of sensor::paramsFromProfile (the
/// refraction offset as glass_offset_m when fixed, else 0); no value is marked fitted.
SensorProfile profileFromParams(const sensor::SensorParams& p);

}  // namespace glassmap::localize
