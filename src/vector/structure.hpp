#pragma once
// Private to vector/: structure versus clutter (the step after the plain fit, see vectorize.hpp).
//   directions.cpp  the building's wall directions from the data, pieces snapped onto them
//   lines.cpp       collinear pieces -> wall lines; gaps bridged or kept open (doors) by their cost
//   clutter.cpp     which lines are the building and which are furniture
//   rooms.cpp       free space split at walls and doors -> room polygons

#include <vector>

#include "grid_util.hpp"
#include "piece.hpp"

namespace glassmap::vector::detail {

/// What a sample of the grid under a wall line shows.
enum class Seen : std::uint8_t {
  Hit,       ///< an occupied cell on the line or a cell either side: the wall (or clutter on it)
  Glass,     ///< a glass cell: a pane fills the gap
  Free,      ///< free on the line and on both sides: a passage seen open
  Occluded,  ///< not seen, but free space (the room) lies within occlusion_depth: hidden by clutter
  Unseen,    ///< not seen and nothing of the room near: unexplored or solid
};

/// A wall line: pieces along one direction at one offset (grid frame), and what became of them.
struct WallLine {
  Vec2 d = Vec2::UnitX();            ///< unit direction
  double offset = 0.0;               ///< n . p for points p on the line, n = (-d.y, d.x) [m]
  int direction = -1;                ///< index into the dominant directions, -1: off every one
  std::vector<std::size_t> members;  ///< indices of the wall pieces on it
  double support = 0.0;              ///< summed member length [m]
  Vec2 normal() const { return {-d.y(), d.x()}; }
};

/// An opening kept in a wall line: a gap seen free. A door when it is door-wide and a passage.
struct Opening {
  Vec2 a = Vec2::Zero(), b = Vec2::Zero();  ///< jambs (grid frame) [m]
  bool door = false;
  std::size_t left = 0, right = 0;  ///< the joined pieces either side (indices into joinLines' result)
};

/// What the structure step made of the wall pieces.
struct Structure {
  std::vector<double> directions;  ///< dominant wall directions in [0, pi) [rad]
  std::vector<Piece> walls;        ///< the building's walls
  std::vector<Piece> clutter;      ///< furniture and other clutter
  std::vector<Opening> openings;   ///< gaps kept open (doors among them)
  std::size_t lines = 0, bridged = 0, snapped = 0;
};

// directions.cpp
/// Dominant directions: peaks of the length-weighted histogram of piece directions (mod pi).
std::vector<double> dominantDirections(const std::vector<Piece>& walls, const std::vector<Piece>& glass,
                                       const Context& ctx);
/// Rotates each piece within the snap angle of a direction onto it (about its middle); returns the
/// direction index per piece (-1: none).
std::vector<int> snapToDirections(std::vector<Piece>& pieces, const std::vector<double>& directions,
                                  const Context& ctx);
// lines.cpp
/// What the grid shows at p on a line with unit normal n.
Seen seenAt(const Vec2& p, const Vec2& n, const Context& ctx);
/// Groups pieces into lines (same direction, offsets within line_tolerance).
std::vector<WallLine> groupLines(const std::vector<Piece>& walls, const std::vector<int>& direction,
                                 const std::vector<double>& directions, const Context& ctx);
/// Each line's pieces joined along it: gaps bridged when their cost is below a segment's, kept
/// open otherwise (openings recorded); a wall running through a gap, or a pane lying in it, stops
/// it. Returns the pieces of every line, and the line of each.
std::vector<Piece> joinLines(const std::vector<WallLine>& lines, const std::vector<Piece>& walls,
                             const std::vector<Piece>& glass, const CellCloud& cloud, const Context& ctx,
                             std::vector<std::size_t>& line_of, Structure& out);
// clutter.cpp
/// Splits the joined pieces into the building's walls and clutter (clutter as `fitted`, the pieces
/// before snapping and joining).
void separateClutter(std::vector<Piece> joined, const std::vector<std::size_t>& line_of,
                     const std::vector<WallLine>& lines, const std::vector<Piece>& glass, const Components& free,
                     const std::vector<Piece>& fitted, const Context& ctx, Structure& out);

// rooms.cpp
/// Rooms: the regions the walls, panes and openings up to door_max wide close off, inside the map.
std::vector<RoomPolygon> segmentRooms(const std::vector<Piece>& walls, const std::vector<Piece>& glass,
                                      const std::vector<Opening>& openings, const Context& ctx);

/// The whole step.
Structure extractStructure(std::vector<Piece> walls, const std::vector<Piece>& glass, const CellCloud& cloud,
                           const Context& ctx);

}  // namespace glassmap::vector::detail
