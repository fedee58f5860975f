#pragma once
/// Walls placed where the scans put them. The vectorizer fits lines to cells: a cell's centre is
/// up to half a cell off the surface, one-sided walls sit on the face of free space as the cells
/// draw it, and pieces whose offsets differ by under line_tolerance share one line across rooms
/// (on a SLAM map that bends, 5-15 cm off parts of it). A plan is meant to explain the returns
/// it was mapped from, and a localizer weighs it by them: each wall and clutter segment is moved
/// along its normal (its direction kept: the building's directions, parallels and right angles
/// stay) onto the densest band of the returns nearest to it, when that explains clearly more of
/// them; ends that met another segment (corners, T junctions) and doors follow to the new lines.
/// Glass stays where the glass evidence put it.

#include <cstddef>

#include "glassmap/core/laser_scan.hpp"
#include "glassmap/grid/scan_integration.hpp"
#include "glassmap/vector/vectorize.hpp"

namespace glassmap::vector {

/// What counts as a segment's evidence and when it moves.
struct ScanFitOptions {
  bool enabled = true;               ///< false: the plan stays as the cells drew it
  double reach = 0.2;                ///< returns within this of a segment (the nearest one) are its evidence [m]
  double max_range = 8.0;            ///< only returns nearer than this (far ones carry the pose's heading error) [m]
  double band = 0.05;                ///< the line moves to the mean of the densest band this half-wide [m] ...
  double min_gain = 0.02;            ///< ... when that band then holds this share of its evidence more than
                                     ///< the band about the line as drawn ...
  double tolerance = 0.10;           ///< ... and no fewer returns lie within this of it [m] (what eval rays counts)
  std::size_t min_returns = 20;      ///< ... and a segment with fewer returns stays [-]
  double bin = 0.005;                ///< resolution of the offsets [m]
  double junction = 1e-3;            ///< an end this close to another segment's line met it there [m]
  double junction_angle_deg = 30.0;  ///< ... when the two cross at least this steeply [deg]
};

/// What a fit did.
struct ScanFitStats {
  std::size_t returns = 0;        ///< returns assigned to some segment
  std::size_t segments = 0;       ///< wall and clutter segments with enough returns to judge
  std::size_t moved = 0;          ///< of them, moved
  double mean_shift = 0.0;        ///< mean |shift| of the moved ones [m]
  double band = 0.0;              ///< the band's half-width of the fit [m] ...
  double explained_before = 0.0;  ///< share of the assigned returns within `band` of their segment ...
  double explained_after = 0.0;   ///< ... before and after [-]
  std::size_t junctions = 0;      ///< segment ends re-joined to a moved line
  double seconds = 0.0;
};

/// Moves the walls and clutter of `plan` (map frame of `log`'s laser poses) onto the returns of
/// `log`'s beams (as `beams` selects them: the mapping's own). Deterministic on any thread count.
ScanFitStats fitToScans(VectorizeResult& plan, const LaserLog& log, const grid::BeamOptions& beams,
                        const ScanFitOptions& options = {});

}  // namespace glassmap::vector
