#pragma once
/// The layers of a floorplan beside its walls and glass: CLUTTER (furniture and other clutter the
/// vectorizer kept apart from the building), DOOR (door openings: the gap between two jambs on a
/// wall line) and ROOMS (room polygons). Written into GPKG (layers clutter, doors, rooms), GeoJSON
/// (features with a `layer` member CLUTTER, DOOR or ROOM) and DXF (layers CLUTTER, DOOR, ROOMS);
/// Shapefile and FlatGeobuf hold one layer and keep the walls and glass only. readFloorplan skips
/// these layers (they are not surfaces a laser localizes against unless asked: FloorplanReadOptions).

#include <cstddef>
#include <filesystem>
#include <vector>

#include "glassmap/core/pose2.hpp"
#include "glassmap/geometry/vector_map.hpp"
#include "glassmap/io/floorplan.hpp"

namespace glassmap {

/// A door opening on a wall line: its two jambs [m].
struct DoorOpening {
  Vec2 a = Vec2::Zero(), b = Vec2::Zero();
  double width() const { return (b - a).norm(); }
};

/// A room: its outline (counter-clockwise, not closed: the last vertex is not the first) [m].
struct RoomPolygon {
  std::vector<Vec2> ring;
  double area = 0.0;  ///< [m^2]
  int id = 0;         ///< 1, 2, ... in order of the vectorizer
};

/// The extra layers of a floorplan.
struct FloorplanExtras {
  VectorMap clutter;  ///< segments that are not the building (material wall)
  std::vector<DoorOpening> doors;
  std::vector<RoomPolygon> rooms;
  bool empty() const { return clutter.segments.empty() && doors.empty() && rooms.empty(); }
  /// Features the extra layers add to a file.
  std::size_t features() const { return clutter.segments.size() + doors.size() + rooms.size(); }
};

/// writeFloorplan with the extra layers (in GPKG, GeoJSON and DXF; Shapefile and FlatGeobuf get
/// the walls and glass only), in the building's CRS when `georef` is given (see floorplan.hpp).
void writeFloorplan(const std::filesystem::path& path, const VectorMap& map, const FloorplanExtras& extras,
                    const FloorplanGeoref* georef = nullptr);

/// The extra layers of a floorplan glassmap wrote (empty for any other file), in metres and, for a
/// GPKG that records its map frame's origin, in the map frame.
FloorplanExtras readFloorplanExtras(const std::filesystem::path& path);

}  // namespace glassmap
