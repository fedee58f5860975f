#pragma once
/// ROS map_server maps: a YAML file plus an image (PGM), with nav_msgs/OccupancyGrid semantics.

#include <cstdint>
#include <filesystem>
#include <vector>

#include "glassmap/core/pose2.hpp"

namespace glassmap {

/// An occupancy grid as nav_msgs/OccupancyGrid holds it: row-major, row 0 is the BOTTOM row
/// (y = origin.y), cell values -1 unknown, 0..100 occupancy probability in percent.
struct OccupancyGridMap {
  int width = 0;                  ///< cells along x
  int height = 0;                 ///< cells along y
  double resolution = 0.05;       ///< cell size [m]
  Pose2 origin;                   ///< pose of the lower-left corner of cell (0, 0) in the map frame [m, rad]
  std::vector<std::int8_t> data;  ///< width * height values, index = row * width + col
  /// The image's occupancy of every cell before the thresholds, (255 - v) / 255 (negate: v / 255),
  /// in [0, 1], same index as data; empty in raw mode and for grids not read from an image. What
  /// trinary mode reads as unknown between the thresholds keeps its shade here: a dark line a blur
  /// or a resampling left lighter than occupied_thresh can still be told from the grey about it.
  std::vector<float> occupancy;
  double occupied_thresh = 0.65, free_thresh = 0.196;  ///< the thresholds `data` was read with

  /// Value of cell (col, row); row 0 is the bottom row.
  std::int8_t at(int col, int row) const { return data[static_cast<std::size_t>(row) * width + col]; }
};

/// Reads a map_server YAML (image, resolution, origin, negate, occupied_thresh, free_thresh,
/// mode trinary|scale|raw) and its image (PGM P5/P2 read directly; other formats such as PNG
/// through GDAL). The image path is relative to the YAML file. Throws Error naming the file and key.
OccupancyGridMap readRosMap(const std::filesystem::path& yaml_path);

/// Writes `<stem>.yaml` and `<stem>.pgm` (P5) as map savers do, in trinary mode: occupied
/// (>= 65) -> 0, free (<= 19) -> 254, unknown and in-between -> 205; the image's top row is the
/// grid's top row. The YAML declares occupied_thresh 0.65 and free_thresh 0.196 (ROS 1's
/// map_saver value): with nav2's 0.25, a reloaded 205 pixel would read as free. Both files are
/// written atomically. `yaml_path` may be given with or without the .yaml extension.
void writeRosMap(const std::filesystem::path& yaml_path, const OccupancyGridMap& map);

}  // namespace glassmap
