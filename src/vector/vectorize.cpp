// vectorize(): the order of the steps (see piece.hpp for the file of each), and pieces -> segments.
#include "glassmap/vector/vectorize.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "glassmap/core/angles.hpp"
#include "structure.hpp"

namespace glassmap::vector {

MaterialOptions VectorizeOptions::glassDefaults() {
  MaterialOptions o;
  o.max_distance = 0.06;
  o.max_angle_deg = 15.0;  // three 5-degree bins either side
  o.neighbour_radius = 0.11;
  o.min_cells = 6;
  o.min_length = 0.40;
  o.min_elongation = 5.0;
  o.max_gap = 0.30;
  o.merge_gap = 0.30;
  o.max_bridge = 1.0;
  o.merge_angle_deg = 6.0;
  o.merge_offset = 0.10;
  o.thickness = 0.01;
  return o;
}

MaterialOptions VectorizeOptions::wallDefaults() {
  MaterialOptions o;
  o.max_distance = 0.10;
  o.max_angle_deg = 20.0;
  o.neighbour_radius = 0.11;
  o.normal_radius = 0.16;
  o.min_cells = 8;
  o.min_length = 0.50;
  o.min_elongation = 2.5;
  o.max_gap = 0.50;  // real walls are seen in patches; doors (0.8 m and up) stay open
  o.merge_gap = 0.50;
  o.max_bridge = 2.0;
  o.merge_angle_deg = 6.0;
  o.merge_offset = 0.10;
  o.thickness = 0.10;
  return o;
}

namespace {

using detail::CellCloud;
using detail::Context;
using detail::Piece;
using namespace detail;  // the steps

std::vector<Piece> fitMaterial(const CellCloud& cloud, Material material, const MaterialOptions& mo, Context& ctx) {
  std::vector<Piece> pieces;
  if (cloud.points.empty()) return pieces;
  if (material == Material::Glass && ctx.opt.glass_voting) {
    glassPiecesByVoting(cloud, mo, ctx, pieces);
  } else {
    detail::GrowParams gp;
    gp.max_distance = mo.max_distance;
    gp.max_angle_deg = mo.max_angle_deg;
    gp.radius = mo.neighbour_radius;
    gp.min_region = ctx.opt.min_region_cells;
    const auto regions = detail::growRegions(cloud, gp);
    ctx.stats.regions += regions.size();
    for (const auto& r : regions) piecesOfRegion(r, cloud, material, mo, ctx, pieces);
  }
  mergeCollinear(pieces, cloud, material, mo, ctx);
  compact(pieces);
  if (material == Material::Wall) {
    ctx.wall_thickness = buildingWallThickness(pieces, ctx);
    mergeFaces(pieces, cloud, ctx);
    compact(pieces);
    mergeCollinear(pieces, cloud, material, mo, ctx);
    compact(pieces);
  }
  filterPieces(pieces, material, mo, cloud, ctx);
  return pieces;
}

MapSegment toSegment(const Piece& p, Material material, const CellCloud& cloud, const LabelGrid& grid,
                     const MaterialOptions& mo) {
  MapSegment s;
  s.a = p.a();
  s.b = p.b();
  s.material = material;
  s.thickness = material == Material::Glass ? mo.thickness : p.thickness;
  s.pane_angle = material == Material::Glass ? wrapHalfTurn(std::atan2(p.d.y(), p.d.x()) + 0.5 * kPi) : 0.0;
  s.support = static_cast<std::uint32_t>(p.ids.size());
  if (!grid.evidence.empty()) {
    double sum = 0;
    for (const std::uint32_t i : p.ids) sum += grid.evidence[static_cast<std::size_t>(cloud.cell[i])];
    s.evidence = p.ids.empty() ? 0.0 : sum / static_cast<double>(p.ids.size());
  }
  return s;
}

}  // namespace

MaterialOptions wallsOnGrid(MaterialOptions mo, double resolution) {
  mo.max_distance = std::max(mo.max_distance, kWallBandCells * resolution);
  mo.neighbour_radius = std::max(mo.neighbour_radius, kWallNeighbourCells * resolution);
  mo.normal_radius = std::max(mo.normal_radius, kWallNormalCells * resolution);
  return mo;
}

VectorizeResult vectorize(const LabelGrid& grid, const VectorizeOptions& given) {
  const auto start = std::chrono::steady_clock::now();
  grid.validate();
  VectorizeOptions options = given;
  options.wall = wallsOnGrid(given.wall, grid.resolution);
  VectorizeResult result;
  VectorizeStats& stats = result.stats;
  const double floor_m = options.noise_floor * grid.resolution;
  Context ctx{grid, options, stats, floor_m * floor_m, options.max_wall_thickness};

  const CellCloud glass_cloud = makeCloud(grid, Material::Glass, options.glass);
  const CellCloud wall_cloud = makeCloud(grid, Material::Wall, options.wall);
  stats.glass_cells = glass_cloud.points.size();
  stats.wall_cells = wall_cloud.points.size();
  std::vector<Piece> glass, walls;
  if (options.glass_segments) glass = fitMaterial(glass_cloud, Material::Glass, options.glass, ctx);
  if (options.walls) walls = fitMaterial(wall_cloud, Material::Wall, options.wall, ctx);

  if (options.face_align) alignOneSidedWalls(walls, wall_cloud, ctx);
  std::vector<Piece> clutter;
  std::vector<detail::Opening> openings;
  const bool structure = options.structure.enabled && !walls.empty();
  if (structure) {
    detail::Structure st = detail::extractStructure(std::move(walls), glass, wall_cloud, ctx);
    if (options.regularize) detail::snapToDirections(glass, st.directions, ctx);
    walls = std::move(st.walls);
    clutter = std::move(st.clutter);
    // The lines join a thick wall's faces that doors, furniture and junctions broke into pieces too
    // short to merge before: the faces of the joined lines merge now.
    mergeFaces(walls, wall_cloud, ctx);
    compact(walls);
    for (const double d : st.directions) stats.directions_deg.push_back(rad2deg(d));
    stats.dominant_axis_deg = st.directions.empty() ? 0.0 : rad2deg(std::fmod(st.directions.front(), 0.5 * kPi));
    stats.lines = st.lines;
    stats.bridged = st.bridged;
    stats.regularized = st.snapped;
    stats.openings = st.openings.size();
    for (const detail::Opening& op : st.openings)
      if (op.door) result.extras.doors.push_back({op.a + grid.origin, op.b + grid.origin});
    openings = std::move(st.openings);
  } else if (options.regularize && !walls.empty()) {
    const double axis = dominantAxis(walls, ctx);
    stats.dominant_axis_deg = rad2deg(std::fmod(axis + kPi, 0.5 * kPi));
    regularize(walls, axis, ctx);
    regularize(glass, axis, ctx);
  }
  if (options.corner_snap > 0) snapCorners(glass, walls, ctx);
  if (structure) {
    result.extras.rooms = detail::segmentRooms(walls, glass, openings, ctx);
    for (RoomPolygon& r : result.extras.rooms)
      for (Vec2& p : r.ring) p += grid.origin;
  }

  result.map.segments.reserve(glass.size() + walls.size());
  for (const Piece& p : glass)
    result.map.segments.push_back(toSegment(p, Material::Glass, glass_cloud, grid, options.glass));
  for (const Piece& p : walls)
    result.map.segments.push_back(toSegment(p, Material::Wall, wall_cloud, grid, options.wall));
  for (const Piece& p : clutter)
    result.extras.clutter.segments.push_back(toSegment(p, Material::Wall, wall_cloud, grid, options.wall));
  for (VectorMap* m : {&result.map, &result.extras.clutter})
    for (MapSegment& s : m->segments) {  // grid frame -> map frame
      s.a += grid.origin;
      s.b += grid.origin;
    }
  stats.wall_thickness = ctx.wall_thickness;
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace glassmap::vector