#pragma once
/// Occupancy maps other programs made (nav2 map_server YAML + PGM/PNG from slam_toolbox,
/// cartographer, gmapping, map editors; any single-band raster GDAL reads with a geotransform) as
/// the vector stage's input. They know free, occupied and unknown, not glass.
///
/// Walls are the boundary between free space and obstacle, whatever lies behind: an occupied cell
/// with no free cell within `face_cells` is the inside of a solid area (the outside of a building
/// drawn black, a thick wall, a pillar filled in) and becomes unknown, so a solid area contributes
/// its faces only instead of being hatched with parallel lines.

#include <cstddef>
#include <string>

#include "glassmap/core/pose2.hpp"
#include "glassmap/geometry/vector_map.hpp"
#include "glassmap/io/labels_raster.hpp"
#include "glassmap/io/ros_map.hpp"
#include "glassmap/vector/label_grid.hpp"

namespace glassmap::vector {

/// How an occupancy map becomes labels.
struct OccupancyOptions {
  int face_cells = 1;  ///< occupied cells farther than this from every free cell (8-neighbourhood
                       ///< rings) are a solid area's inside and become unknown; < 0 keeps them all
  /// Free space reaches through this many unknown cells first (8-neighbourhood rings): the grey
  /// rim anti-aliasing or resampling leaves along a drawn wall is not a gap between it and the
  /// room. 0: a wall must touch free space within face_cells.
  int rim_cells = 2;
  /// A blur or a resampling turns a wall drawn one or two cells thin lighter than occupied_thresh
  /// (a laser SLAM's walls are such bands): a cell read as unknown whose occupancy lies above
  /// free_thresh by a quarter of the way to occupied_thresh or more and is a peak across the line
  /// it lies on (at least its two neighbours along a row, a column or a diagonal, above one of them)
  /// is occupied. Unknown grey (205, occupancy 0.196) is no peak that high, so a trinary map is read
  /// as before. Needs the image's shades (fromOccupancyRaster, or a map read from an image); false:
  /// thresholds only. tools/plan_bench.py --blur 0.8 (36 maps): wall F1 median 0.965 -> 0.991,
  /// minimum 0.000 -> 0.903; --blur 1.5: 0.957 -> 0.986, 0.000 -> 0.869.
  bool ridges = true;
};

/// What the conversion did.
struct OccupancyStats {
  std::size_t free = 0, occupied = 0, unknown = 0;  ///< cells as read
  std::size_t solid_inside = 0;                     ///< occupied cells dropped as a solid area's inside
  std::size_t ridges = 0;                           ///< unknown cells read as occupied: dark lines (ridges)
};

/// Labels of a ROS occupancy grid (readRosMap: -1 unknown, 0 free, 100 occupied, 1..99 between
/// the thresholds, which is unknown here). The grid's origin yaw is NOT applied: the returned grid
/// lies at the origin's position, unrotated; rotate the fitted floorplan with placeOnPose.
LabelGrid fromOccupancy(const OccupancyGridMap& map, const OccupancyOptions& options = {},
                        OccupancyStats* stats = nullptr);

/// Labels of an occupancy image read as raw pixel values (a PNG + world file, a GeoTIFF): the
/// map_server reading with negate 0, occupancy = (255 - v) / 255: above occupied_thresh occupied,
/// below free_thresh free, unknown between.
LabelGrid fromOccupancyRaster(const LabelRaster& pixels, double occupied_thresh = 0.65, double free_thresh = 0.196,
                              const OccupancyOptions& options = {}, OccupancyStats* stats = nullptr);

/// True when every value of the raster is a label code (0, 1, 2..9, 10 + k for the bins):
/// a labels.tif; false for an occupancy image (205 unknown, 254 free, ...).
bool looksLikeLabelCodes(const LabelRaster& raster, int bins = kDefaultBins);

/// The floorplan moved from a grid's frame (as fromOccupancy returns it) to the map frame of a
/// grid whose lower-left corner lies at `origin` (with its yaw).
VectorMap placeOnPose(VectorMap map, const Pose2& origin);

}  // namespace glassmap::vector
