#pragma once
/// What `glassmap map` writes, from a MapResult: the ROS occupancy map, the label GeoTIFF, a
/// picture of the labels and the floorplan files.

#include <filesystem>
#include <vector>

#include "glassmap/io/floorplan.hpp"

#include "glassmap/glass/evidence.hpp"
#include "glassmap/io/labels_raster.hpp"
#include "glassmap/io/ros_map.hpp"
#include "glassmap/pipeline/map_log.hpp"

namespace glassmap::pipeline {

/// ROS map of the labels: unknown -1, empty 0, occupied and glass 100 (a navigation stack then
/// avoids glass).
OccupancyGridMap toRosMap(const glass::CellEvidence& evidence);

/// The labels as file codes (core/labels.hpp) on the same grid.
LabelRaster toLabelRaster(const glass::CellEvidence& evidence);

/// The name of the file written last into a map folder (by the caller, e.g. `glassmap map`'s
/// stats.json): writeMapFiles removes it first, so a folder without it holds an incomplete set.
inline constexpr const char* kMapManifest = "stats.json";

/// Writes into `dir` (created if missing): map.yaml + map.pgm, labels.tif, map.png, sensor.yaml
/// (the sensor profile the map was made with: reuse it with --sensor) and, when
/// `floorplan_files` and the result has a floorplan, floorplan.{gpkg,geojson,dxf,svg,png}.
/// Everything is first written into a hidden staging folder inside `dir`; only when every file is
/// complete is the previous run's manifest (kMapManifest) removed, each file renamed into place,
/// and the previous run's floorplan files removed when this run writes none. A failure or a
/// signal before that leaves `dir` as it was. Returns the paths written. With `georef`, the
/// floorplan files are in the building's CRS (the rasters and map.yaml stay in the map frame).
std::vector<std::filesystem::path> writeMapFiles(const std::filesystem::path& dir, const MapResult& result,
                                                 bool floorplan_files = true, const FloorplanGeoref* georef = nullptr);

}  // namespace glassmap::pipeline
