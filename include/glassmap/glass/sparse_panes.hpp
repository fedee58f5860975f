#pragma once
/// Panes too faint for the cell classifiers. A laser whose glass returns only within a degree or two
/// of the normal, and then rarely (a triangulation scanner: peak 0.3, lobe sigma 1 deg), leaves about
/// one return per pane cell over a whole log: never enough for a cell's own statistics, which see a
/// cell crossed a hundred times and hit once. Along the pane those returns still line up, and each
/// carries its pane's normal: it came back from a cell most beams cross, along a beam nearly normal
/// to the line the returns form. So every such "weak" return votes for one line (normal angle =
/// its beam direction, offset = its position along that normal), and a run of votes along a line is
/// a pane when
///  - a contrario, that many cells of the run would not hold such returns by chance (binomial tail
///    against the density of weak returns of that direction, over the observed cells and around the
///    run, times the number of lines and runs tried: far fewer than one false alarm expected);
///  - the beams that meet the run mostly pass it and end well beyond (glass, not the front of a wall
///    whose returns range noise spreads over two cells); a beam that brings no echo back passes
///    every cell before the first wall it meets and well short of the end of its range (a facade
///    over open ground has nothing in range behind it; a wall's dropouts stop at the wall, and a
///    surface at the edge of the range reads beyond it as often as not);
///  - it is static: a pane answers each beam near its normal on its own, whenever it comes (with the
///    probability its lobe gives the beam's incidence), while a person walking by answers every
///    beam of a scan while there and none before or after, so the near-normal beams of one scan
///    return together far more often than their rates multiply (scan_coherence.hpp: the score
///    test for within-scan correlation, one-sided p below max_transient_p, and a correlation of at
///    least min_transient_correlation); the test by the robot's visits leaves out the near-normal
///    beams another candidate folded on their way (they passed its line and their readings, mirrored
///    back across it, fall on a surface: a glass room's far pane seen through its near one);
///  - its returns did not come through another pane: beyond a pane, a mirror image it folded (the
///    image of a wall seen via the pane at the wall's normal has the same signature) and a wall seen
///    through it at grazing incidence (shifted sideways by the pane, it lands in front of itself)
///    look like faint panes. (A faint pane seen only through another is therefore not found.)
/// Found panes are drawn into the labels (glass along the run, on cells labelled empty).

#include <cstddef>
#include <vector>

#include "glassmap/glass/evidence.hpp"
#include "glassmap/glass/scan_coherence.hpp"
#include "glassmap/grid/scan_integration.hpp"

namespace glassmap::glass {

/// Parameters of the sparse-pane search.
struct SparsePaneOptions {
  double min_range = 0.3;       ///< nearer returns are not weak returns (dust, the robot itself) [m]
  double max_footprint = 3.0;   ///< ...and farther than where the beam spreads over this many cells
  double through_margin = 0.3;  ///< a beam passes a cell when it returns at least this far beyond it
                                ///< (or brings no echo and meets no wall before it) [m]
  int min_through = 3;          ///< a weak return's cell is passed by at least this many beams
  double max_hit_ratio = 0.5;   ///< ...and returns at most this share of the beams that reach it
  double wall_clearance = 0.1;  ///< returns this close to an occupied cell are not weak [m] (at least 3 sigma(r))
  double angle_tol_deg = 3.0;   ///< a return belongs to a line when its beam is this close to the normal [deg]
  double offset_tol = 0.1;      ///< ...and it lies this close to the line [m] (at least 2.5 range sigma)
  /// A cell counts for a line only when this share of its returns came within specific_tol_deg of
  /// the line's normal [fraction, deg]. 0 (the default since stop 53) turns the per-cell test off:
  /// a share of returns is not a rate, and a laser that answers a pane now and then at every angle
  /// (a floor of direct returns) brings a cell more returns off the normal, from the many beams
  /// that meet it there, than near it; the run-level test of min_lobe_contrast takes its place.
  double specific_tol_deg = 10.0;
  double min_specific = 0.0;
  double max_gap = 1.0;            ///< a run of returns along a line breaks at a longer gap [m],
  double gap_factor = 6.0;         ///< ...or one longer than this many median gaps between its cells
  double min_length = 0.3;         ///< shorter runs are not panes [m]
  int min_returns = 5;             ///< fewer returns are not a pane
  double background_margin = 1.0;  ///< chance is judged against the density of weak returns this close [m]
  /// A run is a pane when log10(expected false alarms) is below this. Not 0 (one false alarm): weak
  /// returns are not independent (one object answers many beams of consecutive scans), so the
  /// binomial null is optimistic. Measured: panes of simulated weak lasers score -30 to -290, runs in
  /// the real CARMEN logs (no glass truth) -1 to -49, most of them above -10.
  double log10_max_nfa = -10.0;
  double min_transmission = 0.5;  ///< share of the beams meeting the run that pass it and end beyond
  /// A pane returns at least this share of the beams that meet it within angle_tol_deg of its
  /// normal (sparse::kLeastNormalRate, with its measurements). A run whose near-normal beams came
  /// back less often, at a one-sided binomial p below max_faint_p, is no pane: people crossing a
  /// corridor far down the robot's line of sight, hit now and then over hundreds of scans. 0 turns
  /// the test off.
  double min_normal_rate = sparse::kLeastNormalRate;
  double max_faint_p = 1e-3;
  /// A pane answers near its normal more often than at other angles. Against the rate at which the
  /// beams meeting a run at other angles return on it (or just behind it), its near-normal beams
  /// must return more often (one-sided binomial p below max_faint_p), and not less often than this
  /// many times that rate (at the same p): else it is no pane. Corners, posts and wall ends that line
  /// up by chance, bands of a pane's off-normal returns beside it, and the tracks of people answer
  /// every angle alike. Measured on random:112's glass room turned 37 deg (a lobe of peak 0.41, sigma
  /// 3.1 deg, floor 0.07): the panes return 0.22-0.25 near the normal against 0.045-0.049 at other
  /// angles; runs beside them 0.04-0.07 against 0.05; a run 0.5 m before a desk on rplidar-a2's
  /// paper-corridor with people (seed 2) 0.098 against 0.072 (36 of 368: p 0.03 for the first
  /// test, 0.006 for the second). 0 turns the test off.
  double min_lobe_contrast = 2.0;
  double beyond = 0.3;         ///< ...at least this far past the line [m] (at least 5 sigma(r))
  double glass_margin = 0.15;  ///< a return crossed another pane when it did this far before it [m]
  int min_pane_cells = 4;      ///< ...in a glass cell with this many glass cells in its 5 x 5 block
  double max_via = 0.5;        ///< a run is not a pane when this share of its returns crossed another
  /// A run is a transient (people walking by) when, for a static surface, the near-normal beams of
  /// its scans would return together this rarely (one-sided p of the within-scan correlation's
  /// score test)...
  double max_transient_p = 1e-3;
  /// ...and they share at least this much of their variation within scans: a transient answers all
  /// or none (near 1 while there), while a pane's beams share only what their scan shares (its pose
  /// error moves every incidence at once; a pane covering part of a run answers the scans beside
  /// it). With many beams that small share is significant, hence this floor. Measured on simulated
  /// logs (six lasers, four scenes): panes the other tests keep 0.15 at most; people's runs 0.07 to
  /// 1, most above 0.3 (those below it are kept as panes).
  double min_transient_correlation = 0.25;
  /// A run whose near-normal beams came in one of the robot's visits only has no other visit to
  /// vouch for it standing still (the visit test below cannot speak), so the within-scan test asks
  /// less of it: p below this, with the same correlation floor. Measured on simulated logs (8 named
  /// and 14 random lasers on four glass scenes; 5 lasers on three scenes with 5 people per 100 m^2,
  /// seeds 1-4): panes seen in one visit correlate 0.13 at most (z 2.2 there, most near 0), people's
  /// one-visit runs that the 1e-3 kept up to 0.47 at z 2.0-2.7. It rejected 9 runs over the people
  /// logs and none without people. 0, or anything up to max_transient_p: no other run than the test
  /// above rejects.
  double max_one_visit_transient_p = 0.05;
  /// A run is also a transient when its near-normal beams return together by visit (the robot's
  /// passes along its normal, max_visit_gap_s apart at least: glass/scan_coherence.hpp
  /// visitCoherence) as rarely for a static surface, and share at least min_visit_correlation of
  /// their variation: a person answers the one visit it was there for. Off with max_visit_gap_s 0.
  /// A pane's rate moves from visit to visit with the robot's range and path, so z alone would drop
  /// panes: measured on simulated logs (39 random and 8 named lasers, five scenes, people), the
  /// panes kept correlate at most 0.016 by visit where z passes, people's runs that the within-scan
  /// test kept 0.029 to 0.093; 0.02 lies between (chosen there, not derived: 0.03 kept a person's
  /// run at 0.029 on rplidar-a2's paper-corridor, 0.842 -> 0.650).
  double max_visit_gap_s = 2.0;
  double min_visit_correlation = 0.02;
  /// A run is also a transient when its near-normal beams return together at one place moments
  /// apart (pairs of beams of different scans at most max_place_dt_s apart in time and max_place_ds
  /// along the run: glass/scan_coherence.hpp placeCoherence), at the within-scan test's p (its
  /// one-visit p for a run seen in one visit) and correlation floor: a person walking along the
  /// run's line far down the robot's line of sight, whose near-normal beams meet a stretch of the
  /// line wider than the person, answers the beams at its place scan after scan. Measured on
  /// simulated logs (5 lasers on three scenes, 5 people per 100 m^2, seeds 1-4): the people's runs
  /// the tests above kept on glass-free floors correlate 0.29-0.54 there (z 8-26); panes of eight
  /// named lasers on five scenes 0.15 at most, the default laser's glass room 0.21 (its pose error,
  /// which its scans share as well). At 40 Hz (four lasers on three scenes) a kept pane reached
  /// 0.246 (random:3's glass room; 0.193 within scans): pairs at one place share their incidence,
  /// so a pose error moves both along the lobe alike, where a scan's beams straddle it. The margin
  /// is thin there. 0.25 s: a walking person moves about a third of a metre, about its width;
  /// 0.15 m, half of it. Off with max_place_dt_s 0.
  double max_place_dt_s = 0.25;
  double max_place_ds = 0.15;
  double lobe_bin_deg = 0.5;     ///< return rates near the normal are estimated per incidence bin this wide [deg]
  double range_sigma = 0.0;      ///< the laser's range noise [m]: sigma(r) = hypot(range_sigma,
  double range_sigma_rel = 0.0;  ///< range_sigma_rel r) widens offset_tol, wall_clearance and beyond
};

/// A pane the search found.
struct SparsePane {
  Vec2 a, b;                       ///< ends of its run [m]
  std::size_t returns = 0;         ///< weak returns along it
  double log10_nfa = 0.0;          ///< log10 of the false alarms expected of a run like it
  double transmission = 0.0;       ///< share of the beams meeting it that passed
  sparse::ScanCoherence by_scan;   ///< how its near-normal beams hang together within scans (z 0: static)
  sparse::ScanCoherence by_visit;  ///< ... and within the robot's visits (visitCoherence; `scans` counts visits)
  sparse::ScanCoherence by_place;  ///< ... and at one place moments apart (placeCoherence; `scans` counts pairs)
};

/// What the search did.
struct SparsePaneStats {
  std::size_t weak_returns = 0;         ///< returns from cells most beams pass
  std::size_t runs_tested = 0;          ///< runs of weak returns along a voted line
  std::size_t panes = 0;                ///< runs accepted as panes
  std::size_t rejected_chance = 0;      ///< runs that chance explains (a contrario)
  std::size_t rejected_opaque = 0;      ///< runs the beams do not pass (a wall's front)
  std::size_t rejected_faint = 0;       ///< runs whose near-normal beams return less often than a pane's
  std::size_t rejected_unspecific = 0;  ///< runs that answer their normal no more than other angles
  std::size_t rejected_transient = 0;   ///< runs whose near-normal beams return scan by scan (people walking by)
  /// ...of those, runs seen in one visit only that only max_one_visit_transient_p rejects
  std::size_t rejected_transient_one_visit = 0;
  std::size_t rejected_one_visit = 0;  ///< runs that answered one of the robot's visits along their normal only
  std::size_t rejected_place = 0;      ///< runs whose near-normal beams return at one place moments apart (people)
  std::size_t rejected_through = 0;    ///< runs seen through another pane (mirror images, shifted walls)
  std::size_t rejected_duplicate = 0;  ///< runs on a pane another run with more returns lies along
  std::size_t cells_labelled = 0;      ///< empty cells relabelled glass
  double metres = 0.0;                 ///< total length of the panes found [m]
  std::vector<SparsePane> found;       ///< the panes, in the order found
};

/// Finds sparse panes in the beams of `log` (as the mapping used them) and draws them into
/// `evidence`'s labels: cells labelled empty along each pane become glass of the pane's normal bin.
/// Other labels are kept.
SparsePaneStats findSparsePanes(const LaserLog& log, const grid::BeamOptions& beams, const SparsePaneOptions& options,
                                CellEvidence& evidence);

}  // namespace glassmap::glass
