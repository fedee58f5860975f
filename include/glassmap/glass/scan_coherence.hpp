#pragma once
/// Whether a run of weak returns came from something static or from something that was there for a
/// moment (glass/sparse_panes.hpp). A pane answers each beam near its normal on its own, with the
/// probability its lobe gives the beam's incidence, whenever the beam comes: two beams of one scan
/// return together no more often than their rates multiply. A person walking by answers every beam
/// that meets it while it is there and none before or after: the returns come scan by scan, all
/// the near-normal beams of a scan together. So the within-scan correlation of the near-normal
/// beams' outcomes, given their incidence (the score test for extra-binomial variation: Tarone
/// 1979, with per-beam rates), is about 0 for a pane and near 1 for a transient.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace glassmap::glass::sparse {

/// The least share of the beams along its normal that a pane returns, the floor below which
/// returns are not a pane's (the sparse-pane search per run, SparsePaneOptions::min_normal_rate; the
/// opaque-glass test per cell). rplidar-a2's faint lobe (peak 0.3, sigma 1 deg) averaged over a 5 deg
/// bin and spread over the cells a pane crosses returns about 0.08-0.15 per cell; a run's beams
/// within 3 deg of its normal, on the sparse panes of 39 random lasers without people
/// (tools/sensor_sweep.py), 0.073 at least; people crossing a corridor far down the robot's line of
/// sight 0.009-0.017 (four logs of 5 people per 100 m^2). The calibration takes a lobe down to a
/// peak of 0.05 (pipeline::MapOptions::min_lobe_peak).
inline constexpr double kLeastNormalRate = 0.05;

/// A beam that met a run within the angle tolerance of its normal: it returned on the run or passed it.
struct NearNormalBeam {
  std::uint32_t run = 0;   ///< the run's index
  std::uint32_t scan = 0;  ///< its scan's index in the log
  float incidence = 0.0f;  ///< angle to the run's normal [rad], absolute
  bool returned = false;   ///< true: returned on the run; false: passed it
  double time = 0.0;       ///< its scan's timestamp [s] (visitCoherence, placeCoherence)
  float along = 0.0f;      ///< where it met the run, along the run's line [m] (placeCoherence)
  bool folded = false;     ///< another candidate's line folded it on its way (left out of visitCoherence)
};

/// How the outcomes of one run's near-normal beams hang together within scans.
struct ScanCoherence {
  double z = 0.0;            ///< score statistic for positive within-scan correlation, N(0,1) for a static surface
  double correlation = 0.0;  ///< within-scan correlation of the outcomes (0: independent beams, 1: all or none)
  std::size_t beams = 0;     ///< near-normal beams
  std::size_t scans = 0;     ///< scans with at least two of them
};

/// The coherence of each run 0..runs-1 from `beams` (any order; sorted in place). Return rates are
/// estimated per run and per incidence bin of width bin_width [rad] (the pane's lobe, measured from
/// its own beams).
std::vector<ScanCoherence> scanCoherence(std::vector<NearNormalBeam>& beams, std::size_t runs, double bin_width);

/// The same test with the robot's visits in place of scans: a visit is a stretch of the run's
/// near-normal beams with no gap over max_gap_s between consecutive ones. A pane answers each
/// visit at its rate, a person only the visit it was there for: every beam of that visit, none of
/// the others. With one visit there is nothing to compare (z = 0).
std::vector<ScanCoherence> visitCoherence(std::vector<NearNormalBeam> beams, std::size_t runs, double bin_width,
                                          double max_gap_s);

/// The same test on pairs of beams of scans 0 < dt <= max_dt_s apart (scans stamped alike pair
/// with none) that met the run at most max_ds apart along it: one place, moments apart. A pane
/// answers each of them on its own; a person answers every beam at its place for as long as it
/// stands there, and a person walking along the run's line far from the robot (whose near-normal
/// beams meet only a few tenths of a metre of it per scan, the person part of that) shows more here
/// than within its scans. `scans` counts the pairs. The pairs share the pose error of scans moments
/// apart and, at one place, their incidence: a pose error moves both along the lobe alike, so a
/// pane's pairs may correlate a little more than its scans' beams (sparse_panes.hpp).
std::vector<ScanCoherence> placeCoherence(std::vector<NearNormalBeam> beams, std::size_t runs, double bin_width,
                                          double max_dt_s, double max_ds);

/// Whether a run is a transient: a static surface would show its z with a one-sided probability
/// below max_p, and its beams share at least min_correlation of their variation within scans (with
/// many beams a small shared part is significant: a pane's scans share their pose error). The test
/// of the sparse-pane search and of the calibration's glass fit.
bool isTransient(const ScanCoherence& c, double max_p, double min_correlation);

}  // namespace glassmap::glass::sparse
