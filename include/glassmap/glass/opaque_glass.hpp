#pragma once
/// Glass is crossed. A cell labelled glass must be passed by beams that end well beyond its pane;
/// where the beams that cross it stop just behind it, it is the front of something opaque: a wall
/// whose returns range noise spreads over the cells in front of it, seen at grazing incidence, has
/// the hit-from-one-angle signature the glass classifiers look for. Such cells take their best
/// non-glass label.
///
/// For every beam that crosses a glass cell (ends beyond it, not in it) and did not go through
/// another pane first (a pane may have folded it: beyond that pane, where its straight continuation
/// ends says nothing; a beam that slipped through a one-cell gap in a pane's labels, passing within
/// a cell of its glass cells, went through it) nor through a wall (an occupied cell not beside
/// glass: such a straight path cannot have been, and between two facing panes the images of images
/// lie beyond the walls behind them, where they would pass those walls' cells), the reading's
/// distance past the pane's line (the cell's normal bin) decides: at least `beyond` (or a
/// no-return reading) is a pass; less is a stop. A glass cell with at least
/// min_crossings such crossings of which fewer than min_transmission passed is opaque; so is one that
/// at least min_unpassed_returns beams returned from and none passed (glass seen only through other
/// glass: the far walls of the rooms behind a glass corridor). A cell too thinly seen for either
/// takes the verdict of its pane: the glass cells connected to it whose normals are at most one
/// bin apart, their crossings and returns pooled (a pane lets light through somewhere along it);
/// a pane that many beams returned from is passed by none when its passes are no more than the
/// laser's spurious readings explain (no-return and far readings at a surface: their share among
/// the readings between two neighbours on one surface, measured in the log's scans).
///
/// A cell too thinly seen for either, whose pane too was reached by no beam directly (every return
/// came through another pane first, and fewer than min_crossings beams passed or stopped at it
/// directly), is not glass either: such evidence cannot tell a pane from the noisy band of a far
/// wall seen through glass (the rooms behind a glass corridor, seen only from the corridor).
///
/// A pane (pooled as above) is also no pane when it is a mirror image drawn in open space: nearly
/// all its returns came through another pane first (the straight continuation of a beam a pane
/// reflected or let through and reflected back), and the beams that reached it directly within
/// half an angle bin of its normal passed it with so few returns that a pane returning 5% of them
/// per cell would give fewer with probability under 1e-3 (a laser whose panes mirror most beams
/// draws such images all around a glass room, where the phantom test below sees no wall to block
/// them; the far side of a glass room seen through its near side returns the beams that reach it
/// directly and stays).
///
/// A glass cell is no pane either when it was there for a moment: a person walking by returns
/// the beams that meet it from the robot's side while it stands there, and the cells it stood in
/// pass every beam before and after, which is the one-sided hit-and-pass signature of glass. The
/// beams that met glass first within half an angle bin of its normal, and returned in that pane or
/// passed it, are tested as the sparse-pane search tests its runs (glass/scan_coherence.hpp):
/// within scans (a pane answers each beam on its own, a person all of a scan's beams or none) and
/// by visit (a person answers the one visit it was there for). They are tested per unit (the
/// connected glass cells of one normal bin: a person seen from one place) and per pane (as
/// above: a person's arc, seen as the robot moved, spans several bins). A cell goes when its unit
/// is a transient, or when its pane is one, the cell returned in one of the pane's visits only and
/// its unit is not plainly still (seen in min_static_scans scans or more, correlating under half
/// the floor): a person standing beside a pane joins it, and the pane pooled with them comes out
/// a transient, but the pane's own cells are a unit that returned all along.

#include <cstddef>
#include <cstdint>

#include "glassmap/glass/evidence.hpp"
#include "glassmap/grid/scan_integration.hpp"

namespace glassmap::glass {

/// Parameters of the transmission test.
struct OpaqueGlassOptions {
  double beyond = 0.3;            ///< a pass ends at least this far past the pane [m] (at least 5 sigma(r))
  double min_transmission = 0.5;  ///< glass passes at least this share of the beams that cross it
  int min_crossings = 5;          ///< fewer crossings decide nothing, unless
  int min_unpassed_returns = 10;  ///< ...this many beams returned from the cell and none passed it
  double range_sigma = 0.0;       ///< the laser's range noise: sigma(r) = hypot(range_sigma,
  double range_sigma_rel = 0.0;   ///< range_sigma_rel r) [m, -]
  /// The transient test (above; max_transient_p 0 turns it off), with the sparse-pane search's
  /// one-sided p, longest gap within a visit [s] and incidence bins for the return rates [deg]
  /// (glass/sparse_panes.hpp SparsePaneOptions, where they are measured). Three differ, read off
  /// every unit and pane of the people sweep's glass-free floors (all people) and of 74 logs of
  /// glass scenes without people (docs/calibration.md, item 7). The least within-scan correlation
  /// is 0.5, not 0.25: a strong laser's pane returns nearly every beam near its normal, and one
  /// scan whose beams all passed throws it far (true units up to 0.42; people's median 0.88). The
  /// least correlation by visit is 0.3, not 0.02: a strong pane's rate moves more from visit to
  /// visit with the robot's range and path (true units up to 0.29 but one, of one cell; people's
  /// median 0.76). And a unit or pane seen in one visit gets no weaker test (the sparse search
  /// asks p < 0.05 of its runs seen once): the classifiers' short pieces of true panes seen once
  /// correlate up to 0.35.
  double max_transient_p = 1e-3;
  double min_transient_correlation = 0.5;
  double min_visit_correlation = 0.3;
  double max_visit_gap_s = 2.0;
  double lobe_bin_deg = 0.5;
  int min_static_scans = 10;  ///< a unit seen in this many scans (two near-normal beams each) can be plainly still
};

/// What the test did.
struct OpaqueGlassStats {
  std::size_t glass_cells = 0;          ///< glass cells tested
  std::size_t decided = 0;              ///< ...decided on their own evidence
  std::size_t decided_by_pane = 0;      ///< ...too thinly seen, decided on their pane's (connected glass
                                        ///< cells with normals at most one bin apart) pooled evidence
  std::size_t relabelled = 0;           ///< ...found opaque and relabelled
  std::size_t images = 0;               ///< ...of them mirror images in open space (see above)
  std::size_t through_glass_only = 0;   ///< ...of them too thinly seen, and only through other glass
  std::size_t panes_tested = 0;         ///< panes whose near-normal beams the transient test read
  std::size_t transient_panes = 0;      ///< ...found transients (people), pooled as panes
  std::size_t transient_cells = 0;      ///< cells relabelled as a transient's (above; among `relabelled`)
  std::uint64_t surface_readings = 0;   ///< readings between two neighbours on one surface
  std::uint64_t spurious_readings = 0;  ///< ...that read nothing or well beyond them
  /// Their share: what a wall lets "through" [-].
  double spuriousShare() const {
    return surface_readings ? static_cast<double>(spurious_readings) / static_cast<double>(surface_readings) : 0.0;
  }
};

/// Relabels the opaque glass cells of `evidence` (see above) by their least-cost non-glass label
/// (empty when the cell has no costs), using the beams of `log` as the mapping used them.
OpaqueGlassStats relabelOpaqueGlass(const LaserLog& log, const grid::BeamOptions& beams,
                                    const OpaqueGlassOptions& options, CellEvidence& evidence);

}  // namespace glassmap::glass
