#pragma once
/// The whole mapping pipeline as one call (DESIGN.md, "The pipeline"):
///
///   log -> grid counts and per-angle statistics -> cell classifier (paper 2.5.3 / 2.5.4)
///       -> MRF (2.5.5) -> sparse panes -> opaque glass -> mirror-phantom test -> vectorization -> pane fit of the cells
///
/// The command line (`glassmap map`), the tests and the bench call this; each step's own module
/// holds its options and its code.

#include <cstddef>
#include <functional>
#include <optional>
#include <string>

#include "glassmap/core/laser_scan.hpp"
#include "glassmap/core/sensor_profile.hpp"
#include "glassmap/glass/mapping.hpp"
#include "glassmap/glass/opaque_glass.hpp"
#include "glassmap/glass/phantoms.hpp"
#include "glassmap/glass/sparse_panes.hpp"
#include "glassmap/mrf/refine.hpp"
#include "glassmap/sensor/calibrate.hpp"
#include "glassmap/vector/scan_clutter.hpp"
#include "glassmap/vector/scan_fit.hpp"
#include "glassmap/vector/vectorize.hpp"

namespace glassmap::pipeline {

/// How cells are labelled: a classifier alone, or the direct classifier refined by the MRF.
enum class MapMethod { Heuristic, Direct, Mrf };

/// "heuristic" / "direct" / "mrf".
const char* toString(MapMethod method);
/// Parses "heuristic" / "direct" / "mrf"; throws Error naming the field "method" otherwise.
MapMethod parseMapMethod(const std::string& name);

/// Everything mapLog needs; each step's options are its own module's.
struct MapOptions {
  MapMethod method = MapMethod::Mrf;
  glass::MappingOptions mapping;  ///< grid, beams, classifiers (mapping.method is set from method)
  mrf::RefineOptions mrf;         ///< used when method == Mrf
  /// Look for panes too faint for the cell classifiers (glass/sparse_panes.hpp). On by default since
  /// runs whose near-normal beams return scan by scan (people walking by) are rejected.
  bool sparse_panes = true;
  glass::SparsePaneOptions sparse;
  bool opaque_glass = true;  ///< glass cells the beams do not pass take a non-glass label (glass/opaque_glass.hpp)
  glass::OpaqueGlassOptions opaque;
  bool phantoms = true;  ///< run the mirror-phantom test
  glass::PhantomOptions phantom;
  bool fit_floorplan = true;         ///< vectorize the labels into a floorplan
  bool prune_unfitted_glass = true;  ///< glass cells no fitted pane explains take their best other
                                     ///< label, and the empty or unknown cells a fitted pane passes
                                     ///< through become glass (fits the floorplan even when
                                     ///< fit_floorplan is off)
  double prune_tolerance = 0.10;     ///< ... farther than this from every glass segment [m]
  vector::VectorizeOptions vectorize;
  /// The floorplan's walls and clutter moved onto the log's returns (vector/scan_fit.hpp); off
  /// with scan_fit.enabled = false.
  vector::ScanFitOptions scan_fit;
  /// The final floorplan's clutter layer chosen to explain the returns its walls and panes leave
  /// (vector/scan_clutter.hpp); off with scan_clutter.enabled = false (the cells' clutter stays).
  vector::ScanClutterOptions scan_clutter;
  /// The laser's profile. Unset and `calibrate` on (the default): the range noise is estimated
  /// from neighbouring readings within scans (sensor::inScanNoise, no map needed), a first pass
  /// maps the log with the thresholds it sets, the rest of the profile is fitted against that
  /// pass's floorplan (sensor/calibrate.hpp), and the map is made again with the thresholds the
  /// profile sets (applyProfile), unless they are the ones the first pass used (then it is the map:
  /// a log whose glass lobe keeps the prior's is mapped once), or the fitted lobe agrees with the
  /// first pass's (peak and sigma within one standard error, floors equal within one or both at
  /// or below the spurious rate p_hit_emp) and the other thresholds are the first pass's: then the
  /// first pass is the map too, and `MapResult::profile` keeps the lobe it was made with (the fit
  /// is in `MapResult::calibration`, and says so among its warnings). Set: used as is, one pass.
  std::optional<SensorProfile> sensor;
  bool calibrate = true;
  /// Fit, re-map: at most this many times. A round whose lobe is within one standard error of
  /// the last round's (peak, sigma and floor), or whose profile sets the thresholds the last pass
  /// used, ends the calibration with the last pass as the map. The first pass maps with the
  /// default lobe, and a faint laser's panes are glass there only where they return most: the
  /// lobe fitted against them is too narrow and faint (random:35: peak 0.17, sigma 9.9 deg, floor
  /// 0.006 against the true 0.32 / 16.9 / 0.09); mapped with it, more of the panes are glass, and
  /// the next fit is closer (0.24 / 13.4 / 0.05). Two rounds by default: a log without glass
  /// whose first pass drew "panes" (door frames, people) fits a lobe that does not settle
  /// (Freiburg 079, `glassmap map --calibration-rounds 1 / 2 / 3`, stats.json `sensor`: peak 0.17 /
  /// sigma 2.0 deg, then 0.19 / 13.7, then 0.13 / 20.0), and a third round mapped it a fourth time
  /// (19.2 s of CPU on one core against 15.7-17.3) for a plan that explained a point fewer returns.
  int calibration_rounds = 2;
  /// The profile's glass lobe (peak, sigma, floor) replaces the direct classifier's. On by
  /// default since the classifier expects each pane cell's share of a pane's returns (PaneLanding):
  /// over 29 random lasers (tools/sensor_sweep.py --modes default,no-lobe) it finds the panes of
  /// faint lasers (glass room random:18 / 21 / 27: 0.72 / 0.52 / 0.96 -> 1.00 / 0.96 / 1.00;
  /// paper-corridor random:16 / 21 / 27: 0.63 / 0.71 / 0.55 -> 0.92 / 0.94 / 0.90) and lowers one
  /// row by more than 0.005 (random:8's paper-corridor 0.94 -> 0.92). An unfitted lobe keeps the
  /// default values (the calibration's prior). The range-noise thresholds always follow the profile.
  bool profile_lobe = true;
  /// When the first pass leaves too few beams on glass to fit the lobe, map once more with a
  /// broad lobe (the search lobe below) and fit against that pass's floorplan; the fit replaces the
  /// prior only when it has the beams (sensor::CalibrationOptions::min_glass_beams). With
  /// profile_lobe and calibration. On by default at stop 33, when the first pass had no range noise
  /// and faint lasers' panes returned too little for it (random:16's glass room: 0 -> 0.83). Off
  /// since the first pass has the in-scan noise: it fits the lobe on every glass scene of 29 random
  /// lasers, so that the search changed no row of the sweep (tools/sensor_sweep.py --modes
  /// rounds1,rounds1-search); it fired where the first pass drew no
  /// glass or only people (glass-free floors: a pass more; with people walking it fitted a peak of
  /// 0.013, min_lobe_peak below).
  bool lobe_search = false;
  /// The lobe of that search: the middle of what scanners show (issue 13: sigma 2-20 deg, peak
  /// 0.3-1, a floor of direct returns at any angle up to 0.15), wide enough that a pane returning
  /// 10-20% of its beams is glass and, on glass-free floors (28 random lasers), nothing is.
  double search_peak = 0.5, search_sigma_deg = 10.0, search_floor = 0.1;
  /// A fitted lobe wider than this by more than two standard errors, and wider than it by more than
  /// the fit's own bias (max_lobe_sigma_bias), is not taken (issue 13: real scanners show 2-20 deg by
  /// their detection threshold). Wider fits come from surfaces the first pass took for panes (door
  /// frames, open doors: Freiburg 079 fits 26.2 +- 2.7 deg, with --no-return-range 8 25.7 deg, Intel
  /// 23.7 deg; Freiburg's plan mapped with `glassmap calibrate`'s 23.4 deg lobe through --sensor
  /// explains 41.3% of its returns with its walls against 42.4%). The map keeps the prior lobe then
  /// and says so among the calibration warnings; a profile given with --sensor is used as is.
  double max_lobe_sigma_deg = 20.0;
  /// How far above the truth the lobe fit reads on lasers whose lobe is that wide, as a share of
  /// max_lobe_sigma_deg: simulated 20 deg lobes with a floor of 0.15 fit 20.1-21.2 deg with standard
  /// errors of 0.1 deg (sick-tim571 on four scenes), so the standard errors alone dropped a true
  /// 20 deg lobe on some logs and not on others (office-floor mapped with the MRF: 0.966 against the
  /// fitted lobe's 0.999) [-].
  double max_lobe_sigma_bias = 0.1;
  /// A fitted lobe whose peak is below this by more than two standard errors is not taken either:
  /// near its normal a pane mirrors the beam straight back (paper 2.1; scanners show peaks of
  /// 0.3-1, issue 13), so a lobe that returns almost nothing there was fitted to surfaces that are
  /// not glass (on a glass-free floor with people walking, the broad search's pass fitted a peak of
  /// 0.013). The same bound is the lowest peak applyProfile gives the classifier.
  double min_lobe_peak = 0.05;
  sensor::CalibrationOptions calibration;
};

/// Sets every sensor-dependent threshold of the mapping steps from a profile, in the units of
/// the grid (options.mapping.resolution): the direct classifier's lobe (peak, sigma, floor; only
/// with options.profile_lobe), the miss margin and sigmoid margin (range noise), the sparse-pane,
/// opaque-glass and phantom tests' margins, the vectorizer's noise floor and line distance, and the
/// band and reach of the walls' fit to the returns. Values are never set below the defaults tuned for a 1-2 cm
/// laser, so a precise laser keeps today's behaviour; a field the caller changed from its
/// default (an explicit command-line option) is kept as given.
/// Returns whether any threshold changed.
bool applyProfile(MapOptions& options, const SensorProfile& profile);

/// A fitted glass lobe too wide (max_lobe_sigma_deg, beyond both its standard errors and the fit's
/// bias max_lobe_sigma_bias) or too faint (min_lobe_peak) to be glass, or whose peak lies within two
/// standard errors of zero (the fit cannot tell it from no direct returns), gives way to `prior`'s lobe
/// (peak, sigma, floor), with the reason among fit.warnings. Returns whether the fitted lobe was kept
/// (true also when no lobe was fitted).
bool keepPlausibleLobe(const MapOptions& options, const SensorProfile& prior, sensor::CalibrationResult& fit);

/// Wall-clock time of each step [s].
struct MapTimes {
  double counts = 0.0, angles = 0.0, classify = 0.0;  ///< grid passes and classifier
  double mrf = 0.0, sparse = 0.0, opaque = 0.0;       ///< later steps (0 when skipped)
  double phantoms = 0.0;                              ///< mirror phantoms (0 when skipped)
  double vectorize = 0.0;                             ///< vectorization (0 when skipped)
  double scan_fit = 0.0;                              ///< walls onto the returns (0 when skipped)
  double scan_clutter = 0.0;                          ///< clutter from the returns (0 when skipped)
  double calibration = 0.0;                           ///< first passes and profile fits (0 when skipped)
  double total = 0.0;                                 ///< the whole call
};

/// The outcome of mapping one log.
struct MapResult {
  glass::CellEvidence evidence;           ///< final labels (after every step) and costs
  glass::MappingStats stats;              ///< grid and classifier figures; glass/occupied counts are final
  mrf::RefineResult mrf;                  ///< MRF figures (zero unless method == Mrf)
  glass::SparsePaneStats sparse;          ///< sparse-pane figures (zero when skipped)
  glass::OpaqueGlassStats opaque;         ///< opaque-glass figures (zero when skipped)
  glass::PhantomStats phantoms;           ///< mirror-phantom figures (zero when skipped)
  vector::VectorizeResult floorplan;      ///< the fitted floorplan (empty unless fitted)
  bool has_floorplan = false;             ///< the floorplan was fitted
  std::size_t pruned_glass = 0;           ///< glass cells the pane fit relabelled
  std::size_t filled_glass = 0;           ///< empty or unknown cells on a fitted pane made glass
  vector::ScanFitStats scan_fit;          ///< the walls moved onto the returns (zero when skipped)
  vector::ScanClutterStats scan_clutter;  ///< the clutter layer chosen from the returns (zero when skipped)
  SensorProfile profile;                  ///< the profile the final pass used
  bool calibrated = false;                ///< profile was fitted from this log
  sensor::CalibrationResult calibration;  ///< the fit of `profile` (when calibrated)
  int passes = 1;                         ///< mapping passes over the log (calibration's included)
  /// Of those, the passes that reused the first's walks over the beams (counts, per-angle
  /// histograms, sigmoid sums: glass::BeamPasses); their seconds.counts and .angles are 0.
  int reused_beam_walks = 0;
  MapTimes seconds;
};

/// progress(stage, fraction): "counts" and "angles" report fractions in [0, 1]; "mrf",
/// "sparse", "opaque", "phantoms", "vectorize" and "calibrate" report 0 when they start and 1 when they end.
using Progress = std::function<void(const char* stage, double fraction)>;

/// Maps a log with the laser poses of its scans. Throws Error for bad options or a log with no
/// scans, and before allocating a grid larger than options.mapping.max_memory_bytes allows.
MapResult mapLog(const LaserLog& log, const MapOptions& options = {}, const Progress& progress = {});

/// What calibrateLog fitted and against what.
struct CalibrateLogResult {
  sensor::CalibrationResult fit;
  bool own_floorplan = false;                            ///< fitted against a floorplan mapped from the log itself
  std::size_t floorplan_walls = 0, floorplan_panes = 0;  ///< segments it was fitted against
  int rounds = 0;                                        ///< mapping passes, each followed by a fit
  double seconds = 0.0;
};

/// The sensor profile of a log's laser: against `floorplan` when given (map frame of the log's
/// laser poses), otherwise against the floorplan mapLog makes of the log, refitted
/// options.calibration_rounds times. Throws Error as mapLog and calibrate do.
CalibrateLogResult calibrateLog(const LaserLog& log, const VectorMap* floorplan, const MapOptions& options = {},
                                const Progress& progress = {});

}  // namespace glassmap::pipeline
