#pragma once
/// Self-calibration: a sensor profile (core/sensor_profile.hpp) estimated from a log against a
/// floorplan, so that no stage has to assume the laser the classifiers were first tuned with.
///
///  1. Each scan's pose is refined against the floorplan's walls (point-to-line Gauss-Newton,
///     damped towards the logged pose), so that pose error does not pass for range noise.
///  2. Beams whose first surface is a wall: EM over the beam-model mixture (Probabilistic Robotics
///     6.3, table 6.2) gives sigma_hit, the hit/short/max/random weights and lambda_short.
///  3. Beams whose first surface is glass: each reading is matched to the pane (direct return), the
///     mirrored ray (reflection) or the continued ray (refraction). Binomial maximum likelihood fits
///     P(direct | theta) = floor + (peak - floor) exp(-theta^2 / 2 sigma^2) and, for beams that did
///     not come back from the pane, P(reflected | theta) = floor + (1 - floor) exp(-lambda (90 - theta));
///     the median extra range of refracted readings is the offset through a pane. Panes whose
///     near-normal beams return scan by scan, all or none (people walking by, drawn as glass by a
///     first pass), are left out first (glass/scan_coherence.hpp).
///
/// Standard errors come from the inverse observed information of each fit. Parameters the log
/// cannot tell (too few glass beams, no reflection ever possible) keep the prior's value and are
/// marked not fitted.

#include <cstddef>
#include <string>
#include <vector>

#include "glassmap/core/laser_scan.hpp"
#include "glassmap/core/sensor_profile.hpp"
#include "glassmap/geometry/vector_map.hpp"

namespace glassmap::sensor {

/// Where sigma_hit comes from: the residuals against the floorplan's walls (EM), or the spread of
/// neighbouring readings within each scan (no map involved: neither the floorplan's drawing error
/// nor pose error enters it; the choice when the floorplan was mapped from the same log), or the
/// prior's range noise and typical range as they are: the Local estimate made before from this
/// very log (inScanNoise, the same scans and fit), not made again.
enum class SigmaSource { Walls, Local, Prior };

struct CalibrationOptions {
  SigmaSource sigma_source = SigmaSource::Walls;
  std::size_t max_scans = 1500;         ///< scans used, spread evenly over the log
  bool align_scans = true;              ///< refine each scan's pose against the walls first
  double align_gate_m = 0.30;           ///< alignment: readings this close to the expected wall [m]
  double max_fit_incidence_deg = 65.0;  ///< wall beams steeper than this stay out of the sigma fit
  double gate_sigmas = 4.0;             ///< a reading within this many sigma of a glass mode is that mode
  double min_gate_m = 0.04;             ///< ... but at least this close [m]
  double pane_end_margin_m = 0.20;      ///< glass beams meeting a pane this close to an end are left out [m]
  /// A pane whose beams within transient_angle_deg of its normal return together within scans
  /// (one-sided p of the score test below max_transient_p, and a within-scan correlation of at least
  /// min_transient_correlation; rates per transient_bin_deg of incidence) is a transient, people
  /// walking by, and stays out of the glass fit: the thresholds of glass/sparse_panes.hpp.
  /// max_transient_p = 0 keeps every pane.
  double transient_angle_deg = 3.0;
  double max_transient_p = 1e-3;
  double min_transient_correlation = 0.25;
  double transient_bin_deg = 0.5;
  std::size_t min_glass_beams = 300;  ///< fewer beams on glass: the glass parameters keep the prior
  double chart_bin_deg = 2.0;         ///< width of the per-angle table [deg]
  int em_iterations = 200;            ///< EM stops here or when no weight moves by 1e-6
  SensorProfile prior;                ///< values kept where the data cannot tell
};

struct CalibrationResult {
  SensorProfile profile;
  std::vector<GlassAngleBin> bins;    ///< the chart's table
  std::size_t scans = 0;              ///< scans used
  std::size_t aligned_scans = 0;      ///< scans whose pose alignment converged
  double median_alignment_m = 0.0;    ///< median position change of the alignment [m]
  double median_alignment_deg = 0.0;  ///< median heading change [deg]
  std::size_t refracted_beams = 0;    ///< readings matched to the continued ray
  double range_sigma_em_m = 0.0;      ///< sigma from the wall residuals (EM) [m]
  double range_sigma_local_m = 0.0;   ///< sigma from neighbouring readings within scans [m] (0: too few)
  std::size_t transient_panes = 0;    ///< glass segments left out of the glass fit as transients
  double transient_length_m = 0.0;    ///< ...their length [m]
  std::vector<std::string> warnings;  ///< what could not be estimated, and why
};

/// The range noise of the log's laser from neighbouring readings within scans, no map involved
/// (the scans and the fit of calibrate's SigmaSource::Local, so that calibrate then gives the same
/// numbers): range_sigma_m, range_sigma_rel and typical_range_m (the median range of the scans'
/// returns) of `profile` set. False, `profile` unchanged, when the scans have too few of them.
bool inScanNoise(const LaserLog& log, const CalibrationOptions& options, SensorProfile& profile);

/// Estimates the profile of the log's laser against `map` (scans at their laser poses, map frame).
/// Throws Error when the log has no scan or the map no wall.
CalibrationResult calibrate(const LaserLog& log, const VectorMap& map, const CalibrationOptions& options = {});

}  // namespace glassmap::sensor
