#pragma once
/// The CLUTTER layer from the returns. The structure step keeps the building (WALL, GLASS) apart
/// from what stands in it, but the clutter it draws from cells is the outline of every occupied
/// blob: many short pieces, most of which few returns touch, while the surfaces that the laser
/// meets most (cabinets, desk fronts, shelves) may be drawn as several. A plan is meant to explain
/// the returns of the log it was mapped from, with few segments: here the clutter layer is chosen
/// as a greedy cover of the returns the building leaves unexplained. Each candidate line is fitted
/// at a seed of dense unexplained returns (orientations swept, the band re-centred, then the
/// principal axis of its returns), grown along its line while its returns leave no gap over
/// `max_gap`, and scored by the returns it explains that no chosen segment explains yet; the best
/// candidate is taken while it explains at least `min_share` of all the returns (lazy greedy: a
/// candidate whose returns another took is refitted before it competes again). The lines never
/// explain less than the cells' pieces did: where they would (a long log of a large floor, whose
/// many small objects are each hit by fewer than `min_share` of its returns), the cells' pieces
/// come back, those whose returns no line took first, until the share is reached again.

#include <cstddef>

#include "glassmap/core/laser_scan.hpp"
#include "glassmap/grid/scan_integration.hpp"
#include "glassmap/vector/label_grid.hpp"
#include "glassmap/vector/vectorize.hpp"

namespace glassmap::vector {

/// What the layer is chosen from and when a segment is worth its place.
struct ScanClutterOptions {
  bool enabled = true;           ///< false: the clutter layer stays as the cells drew it
  double tolerance = 0.10;       ///< a return within this of a segment is explained by it [m] (eval rays)
  double max_range = 8.0;        ///< only returns nearer than this count (eval rays) [m]
  double min_share = 1e-3;       ///< a segment explains at least this share of all the returns [-]
  double min_length = 0.2;       ///< shorter segments are not drawn [m]
  double max_length = 12.0;      ///< a segment reaches at most this far either side of its seed [m]
  double max_gap = 0.5;          ///< its returns leave no longer gap along it [m] ...
  double max_free = 0.15;        ///< ... and it runs through cells seen empty for no longer [m]
  double seed_cell = 0.25;       ///< returns are seeded and looked up in square cells this wide [m]
  double angle_step_deg = 10.0;  ///< orientations tried at a seed [deg]
};

/// What the step did.
struct ScanClutterStats {
  std::size_t returns = 0;        ///< returns under max_range
  std::size_t unexplained = 0;    ///< of them, over `tolerance` from every wall and pane and
                                  ///< not in free space (see clutterFromScans)
  std::size_t replaced = 0;       ///< clutter segments of the cells given up ...
  std::size_t added = 0;          ///< ... clutter segments chosen from the returns ...
  std::size_t restored = 0;       ///< ... and of the cells' given back (see clutterFromScans)
  double explained_before = 0.0;  ///< share of the returns near some segment, walls and clutter as drawn ...
  double explained_walls = 0.0;   ///< ... near a wall or pane alone ...
  double explained_after = 0.0;   ///< ... and with the chosen clutter [-]
  std::size_t candidates = 0;     ///< lines fitted (refits included)
  double seconds = 0.0;
};

/// Replaces the clutter layer of `plan` (in the map frame of `log`'s laser poses) by segments
/// chosen to explain the returns of `log`'s beams (as `beams` selects them) that its walls and
/// panes leave unexplained. With `free_space` (the labels the plan was drawn from; its frame at
/// `grid_pose` in the map frame, as a ROS map's origin with its yaw), returns in free space (their
/// cell and its eight neighbours seen empty: people walking, doors moved) are no surface's, and a
/// segment does not run through cells seen empty. Deterministic on any thread count.
ScanClutterStats clutterFromScans(VectorizeResult& plan, const LaserLog& log, const grid::BeamOptions& beams,
                                  const LabelGrid* free_space, const Pose2& grid_pose = {},
                                  const ScanClutterOptions& options = {});

}  // namespace glassmap::vector
