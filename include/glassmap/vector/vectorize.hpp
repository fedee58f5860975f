#pragma once
/// Vectorisation: glass and wall cells of a label raster -> line segments (a VectorMap).
///
/// Per material: cells are grown into regions (CGAL Shape_detection region growing over cell
/// centres; the normal of a glass cell is its angle label, of a wall cell the local principal
/// axis), each region is fitted by least squares (CGAL linear_least_squares_fitting_2), cut where
/// its cells leave a gap, split while the Bayesian information criterion says two lines explain
/// the cells better than one, clipped to its cells' extent, and collinear neighbours are merged
/// across small gaps when the criterion says one line suffices. Walls then get their two faces
/// merged into a centre line, near-axis segments snapped to the floor's dominant axes (angled
/// glass stays angled), and corners closed.

#include <cstddef>

#include "glassmap/geometry/vector_map.hpp"
#include "glassmap/io/floorplan_extras.hpp"
#include "glassmap/vector/label_grid.hpp"

namespace glassmap::vector {

/// Fitting parameters of one material.
struct MaterialOptions {
  double max_distance = 0.08;        ///< region growing: cell centre to region line [m]
  double max_angle_deg = 20.0;       ///< region growing: cell normal to region normal [deg]
  double neighbour_radius = 0.11;    ///< region growing: cells within this centre distance are neighbours [m]
  double normal_radius = 0.16;       ///< wall cells: radius of the local principal-axis window [m]
  std::size_t min_cells = 6;         ///< fewer supporting cells: dropped
  double min_length = 0.25;          ///< shorter segments: dropped [m]
  double min_elongation = 3.0;       ///< length / measured thickness below this: a blob, dropped
  double min_label_agreement = 0.6;  ///< glass: share of cells whose angle label is within max_angle of the fit
  double max_gap = 0.30;             ///< a region is cut where its cells leave a longer gap [m]
  double merge_gap = 0.30;           ///< collinear pieces closer than this may merge [m]
  double max_bridge = 1.0;           ///< ... and up to this across a gap not seen free (unknown, sparse hits) [m]
  double merge_angle_deg = 6.0;      ///< collinear pieces: direction difference [deg]
  double merge_offset = 0.10;        ///< collinear pieces: endpoint offset from the other's line [m]
  double thickness = 0.10;           ///< thickness written for a segment that has no measured one [m]
};

/// The wall fit's neighbourhoods are set in metres for maps of 0.05 m cells and finer (the band
/// 0.10 m, two cells there; the neighbour radius 0.11 m, 2.2 cells; the normal's window 0.16 m,
/// three cells). On a coarser grid they would shrink below what a wall drawn in cells needs: a
/// face at a slant wanders up to 0.7 cell off its line, the next cell of a face at 45 degrees lies
/// 1.41 cells away, and a normal from a 3 x 3 window of a slanted face is noise. So they are at
/// least kWallBandCells, kWallNeighbourCells and kWallNormalCells cells (nothing changes at 0.05 m
/// and finer). Measured with tools/plan_bench.py --map-extra "--resolution R" (36 test maps each,
/// wall F1 median / min, metres -> cells): R 0.075 0.989 / 0.921 -> 1.000 / 0.943; 0.1 0.923 /
/// 0.749 -> 0.993 / 0.947; 0.15 and 0.2 no wall at all -> 0.985 / 0.902 and 0.979 / 0.908.
inline constexpr double kWallBandCells = 1.5;
inline constexpr double kWallNeighbourCells = 1.6;
inline constexpr double kWallNormalCells = 2.5;
/// The wall options vectorize() fits with on a grid of `resolution` [m]: max_distance,
/// neighbour_radius and normal_radius raised to those floors.
MaterialOptions wallsOnGrid(MaterialOptions wall, double resolution);

/// Structure versus clutter: the building's walls apart from furniture, long walls continued
/// through what hid them, openings kept (see structure.hpp in src/vector for the steps).
/// Costs are in nats of description length, against one segment's 2 * 0.5 ln(N) (N wall cells).
struct StructureOptions {
  bool enabled = true;                    ///< false: the plain fit (every face a wall, one or two axes)
  double peak_share = 0.04;               ///< a wall direction holds at least this share of the wall length [-]
  double direction_separation_deg = 10;   ///< directions closer than this are one [deg]
  double snap_max_deg = 8.0;              ///< a piece snaps to a direction within atan(2 cells / length),
                                          ///< at least 2 and at most this [deg]
  double line_tolerance = 0.10;           ///< pieces of one direction whose offsets differ by less share a line [m]
  double free_cost = 3.0;                 ///< bridging: per cell of gap seen free (a passage) [nats]
  double unseen_cost = 0.5;               ///< ... per cell never seen with no room near (unexplored, solid) [nats]
  double occluded_cost = 0.05;            ///< ... per cell hidden behind clutter, the room within reach [nats]
  double hit_gain = 0.5;                  ///< ... gain per cell where the line was hit [nats]
  double occlusion_depth = 1.5;           ///< a gap is hidden by clutter when free space lies this close [m]
  double door_min = 0.6, door_max = 2.2;  ///< a gap seen free this wide, with free space both sides, is a door [m]
  double min_line_support = 2.0;          ///< a line whose pieces sum to less is clutter (unless it joins walls) [m]
  double off_direction_min_length =
      2.5;                            ///< off every direction, shorter pieces are clutter (unless they join walls) [m]
  double shadow_depth = 1.2;          ///< a short line this close in front of a longer parallel wall ... [m]
  double max_furniture_length = 3.0;  ///< ... and shorter than this is furniture standing against it [m]
  double furniture_depth = 2.5;       ///< a one-sided piece with free space again this close behind it (deeper than a
                                      ///< wall is thick) is an object one walks around (a desk, a pillar) [m]
  double min_room_area = 1.5;  ///< free space enclosed in less is the inside of an object drawn as an outline, not a
                               ///< room [m^2]
};

/// Everything vectorize() needs. Defaults suit 5 cm grids.
struct VectorizeOptions {
  MaterialOptions glass = glassDefaults();
  MaterialOptions wall = wallDefaults();
  double noise_floor = 0.3;          ///< BIC: floor of the rms cell offset from a line [cells]
  double params_per_segment = 4.0;   ///< BIC: free parameters of one segment (line + extent)
  double max_wall_thickness = 0.35;  ///< two parallel wall faces closer than this become one wall [m]
  /// Two faces farther apart than max_wall_thickness, up to this, also become one wall when free
  /// space lies outside both along their overlap and they overlap over at least
  /// structure.max_furniture_length: a thick wall seen from both sides (old masonry, a wall with a
  /// shaft in it). A shorter pair is a desk or a cabinet against a wall (its front and the wall's
  /// other face, solid between, free outside both). max_wall_thickness or less: off [m].
  double max_two_sided_thickness = 0.8;
  double corner_snap = 0.35;  ///< wall ends this close to another wall's line are joined [m]
  /// A pane's end moves onto a wall's line this far (at least corner_snap), and a wall end meets a
  /// pane's line this far beyond the pane's end: a pane ends in a frame, and its last cells are
  /// the ones a pane's evidence and the MRF lose first (seen at the widest angles, next to the
  /// frame). Narrower than any passage, so no doorway beside a pane closes [m].
  double glass_corner_snap = 0.6;
  bool face_align = true;             ///< a wall seen from one side only lies on its observed face (the
                                      ///< edge of free space), not in the middle of its blurred band
  bool regularize = true;             ///< snap near-axis segments to the dominant axes
  double regularize_angle_deg = 3.0;  ///< ... when within this of an axis [deg]; angled glass stays
  bool walls = true;                  ///< fit walls
  /// Glass cells are grouped into panes by voting for lines (each cell near its own angle label),
  /// which finds panes whose cells are sparse (a narrow-lobe or coarse laser hits one pane cell in
  /// three or four); false: region growing over neighbouring cells, as walls.
  bool glass_voting = true;
  /// A pane's cells are cut where their widest gap is this unlikely under the pane's own density
  /// of cells q: m (1 - q)^gap < glass_gap_alpha for m gaps between its cells (m = 1 where the
  /// cells clump, at the same alpha) [-]. Gaps up to glass.max_gap always join, gaps over
  /// glass.max_bridge never.
  double glass_gap_alpha = 0.01;
  /// Voting keeps a pane only when its cells stand out of the glass cells around it: the background
  /// density is counted in a band this far either side (beyond the pane's own) [m].
  double glass_background_ring = 0.5;
  /// ... and when fewer than 10^this such lines would arise by chance from that background in the
  /// whole map (the a contrario number of false alarms; -2: one in a hundred maps) [-].
  double glass_log10_false_alarms = -2.0;
  bool glass_segments = true;  ///< fit glass
  // Finer rules of the steps (defaults suit any cell size; units as stated).
  std::size_t min_region_cells = 3;       ///< region growing: smaller regions are left unassigned [cells]
  double short_glass_sd_cells = 3.0;      ///< a glass piece whose cells spread along it by less than this
                                          ///< (std dev, about 10 cells of length) takes its direction from
                                          ///< the angle labels, not the fit [cells]
  double end_margin_cells = 0.5;          ///< a piece reaches this far past its outermost cell centres [cells]
  double max_unseen_free_fraction = 0.2;  ///< a gap counts as unseen (bridgeable up to max_bridge) when
                                          ///< at most this share of it was seen free [-]
  double face_min_overlap = 0.5;          ///< wall faces merge when they overlap over this share of the
      ///< longer one (a short parallel piece is furniture against the wall, not its other face) [-] ...
  double face_max_free_fraction = 1.0 / 3.0;  ///< ... and at most this share of the band between
                                              ///< them is free space [-]
  /// Two faces farther apart than max_wall_thickness merge only with free space outside both (at
  /// all but face_max_free_fraction of the samples along them), looked for this far out: furniture
  /// against a thick wall hides the room behind it [m].
  double face_outside_reach = 0.7;
  double side_crowding_cells = 1.0;    ///< glass: look this far past the pane's band (voting: twice
                                       ///< glass.max_distance; else one cell) for more glass [cells] ...
  double max_side_crowding = 0.5;      ///< ... a piece with more of its cells crowded is a strip cut out
                                       ///< of a blob, not a pane, and is dropped [-]
  double axis_window_deg = 1.0;        ///< walls within this of a direction count for it as the
                                       ///< dominant axis [deg]
  double corner_min_angle_deg = 30.0;  ///< ends snap only to walls crossing at least this steeply [deg]
  double one_sided_max_ratio = 0.25;   ///< a wall is one-sided when its less free side has at most this
                                       ///< share of its freer side's free samples [-]
  StructureOptions structure;          ///< building versus clutter, doors

  static MaterialOptions glassDefaults();
  static MaterialOptions wallDefaults();
};

/// Counts and times of one run.
struct VectorizeStats {
  std::size_t glass_cells = 0, wall_cells = 0;  ///< input cells per material
  std::size_t regions = 0;                      ///< regions grown (both materials)
  std::size_t bic_splits = 0;                   ///< pieces split by the criterion
  std::size_t merges = 0;                       ///< collinear merges accepted
  std::size_t face_merges = 0;                  ///< wall face pairs merged into a centre line
  /// Faces this far apart or closer are one wall: max_wall_thickness, or the building's own
  /// thicker walls measured from its long walls seen from both sides [m].
  double wall_thickness = 0.0;
  std::size_t face_aligned = 0;        ///< one-sided walls moved onto their observed face
  std::size_t regularized = 0;         ///< segments rotated onto an axis
  std::size_t corners = 0;             ///< segment ends moved to close a corner or T
  std::size_t dropped = 0;             ///< pieces dropped (too short, too few cells, blob)
  std::size_t continued = 0;           ///< glass runs kept as the continuation of an accepted pane
  double dominant_axis_deg = 0.0;      ///< the floor's dominant wall direction in [0, 90) [deg]
  std::vector<double> directions_deg;  ///< structure: the wall directions found in [0, 180) [deg]
  std::size_t lines = 0;               ///< structure: wall lines (pieces grouped by direction and offset)
  std::size_t bridged = 0;             ///< structure: gaps along a line claimed as wall
  std::size_t openings = 0;            ///< structure: gaps kept open (doors among them)
  double seconds = 0.0;                ///< wall-clock time [s]
};

/// The floorplan and how it was obtained.
struct VectorizeResult {
  VectorMap map;           ///< glass segments first, then walls; attributes filled
  FloorplanExtras extras;  ///< clutter, doors, rooms (with structure enabled)
  VectorizeStats stats;
};

/// Vectorises a label raster. Throws Error if the grid is malformed.
VectorizeResult vectorize(const LabelGrid& grid, const VectorizeOptions& options = {});

}  // namespace glassmap::vector
