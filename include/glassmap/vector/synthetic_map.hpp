#pragma once
/// Test maps for the vector stage: a true floorplan rasterised the ways other programs leave an
/// occupancy map, with furniture of several sizes in its rooms, so that a plan's walls can be
/// scored against a known truth (`glassmap bench plan-map`, tools/plan_bench.py, tests/vector).
///
/// Conventions:
///  - solid: a map editor's or a thresholded map: free space is the inside of the building, every
///    other cell (the outside, thick walls, furniture) occupied;
///  - slam: what a laser SLAM leaves: scans from viewpoints spread over every room (range noise,
///    8 m reach) clear free space and mark the surfaces they hit, a band a cell or two thick, with
///    unknown beyond (behind walls, inside furniture, outside the building);
///  - drawn: lines on white: walls and furniture occupied, every other cell free (the outside too).
/// Glass is opaque here (drawn or seen as a wall): the truth is the structure with glass as wall.

#include <cstdint>
#include <string>
#include <vector>

#include "glassmap/geometry/vector_map.hpp"
#include "glassmap/vector/label_grid.hpp"

namespace glassmap::vector {

/// How an occupancy map shows the building.
enum class MapConvention { Solid, Slam, Drawn };

/// "solid", "slam", "drawn".
std::string toString(MapConvention c);
/// Parses a convention name; throws Error naming `field` otherwise.
MapConvention parseMapConvention(const std::string& name, const std::string& field = "convention");

/// What the test map holds and how it is seen.
struct SyntheticMapOptions {
  MapConvention convention = MapConvention::Solid;
  double resolution = 0.05;           ///< cell size [m]
  double margin = 1.0;                ///< grid border around the plan [m]
  double structure_thickness = 0.10;  ///< plan walls at least this thick are structure; thinner ones
                                      ///< (the scenes' desk outlines) are furniture [m]
  bool plan_furniture = true;         ///< draw the plan's thin outlines (desks) too; false leaves them out
  double furniture_cover = 0.08;      ///< share of the floor that added furniture covers [-]
  double bins_per_100m2 = 2.0;        ///< small obstacles (bins, plants, 0.25-0.45 m) per 100 m^2
  double against_wall_share = 0.5;    ///< share of pieces placed against a wall [-]
  double door_clearance = 0.8;        ///< furniture stays this far from free wall ends (door jambs) [m]
  double viewpoint_spacing = 1.0;     ///< slam: viewpoints on a grid this fine in free space [m]
  double viewpoint_clearance = 0.35;  ///< slam: ... at least this far from any surface [m]
  double beam_step_deg = 0.5;         ///< slam: angular step of a scan [deg]
  double max_range = 8.0;             ///< slam: reach of a scan [m]
  double range_sigma = 0.01;          ///< slam: range noise [m]
  double entrance_width = 3.0;        ///< openings to the outside up to this wide do not let it in [m]
  double min_room_area = 3.0;         ///< enclosed pockets smaller than this are solid (desk insides) [m^2]
  std::uint64_t seed = 1;             ///< furniture, viewpoints and noise
};

/// A test map and its truth.
struct SyntheticMap {
  LabelGrid grid;              ///< codes: 1 free, 2 occupied, 0 unknown; origin in the plan's frame
  VectorMap structure;         ///< truth: structural walls and glass, all as wall
  VectorMap furniture;         ///< furniture outlines (added pieces and the plan's thin outlines)
  std::size_t pieces = 0;      ///< furniture pieces added
  std::size_t viewpoints = 0;  ///< slam: scans taken
  double free_area = 0.0;      ///< free cells [m^2]
};

/// Builds the test map of `plan` (walls with thickness; any material) as `options` say.
/// Deterministic for a seed on every platform. Throws Error for an empty plan or a bad option.
SyntheticMap makeSyntheticMap(const VectorMap& plan, const SyntheticMapOptions& options = {});

}  // namespace glassmap::vector
