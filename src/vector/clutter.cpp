// Structure step 3: which joined lines are the building and which are clutter. A wall runs on:
// its line gathers support across rooms, or it is long on its own, or it joins walls at both
// ends (a jog, a closet's side). Furniture is short, off the building's directions, stands in
// front of a longer parallel wall (a shelf, a desk against it), or hangs off walls by one end only
// (a desk's sides).
#include <algorithm>
#include <cmath>
#include <limits>

#include "glassmap/core/angles.hpp"
#include "grid_util.hpp"
#include "structure.hpp"

namespace glassmap::vector::detail {

namespace {

// True when the end `e` of piece p meets piece q: within snap of q's extent, run on by `beyond`
// at either end, crossing it at corner_min_angle_deg or more.
bool meets(const Piece& p, const Vec2& e, const Piece& q, const Context& ctx, double beyond = 0.0) {
  const double cross = std::abs(p.d.x() * q.d.y() - p.d.y() * q.d.x());
  if (cross < std::sin(deg2rad(ctx.opt.corner_min_angle_deg))) return false;
  const double t = std::clamp(q.d.dot(e - q.c), q.t0 - beyond, q.t1 + beyond);
  return (q.at(t) - e).norm() <= ctx.opt.corner_snap;
}

// Overlap of q's extent with p's, along p [m].
double overlapAlong(const Piece& p, const Piece& q) {
  const double u = p.d.dot(q.a() - p.c), v = p.d.dot(q.b() - p.c);
  return std::min(p.t1, std::max(u, v)) - std::max(p.t0, std::min(u, v));
}

// Depth of the non-free space behind a one-sided piece: from stations along it, the distance
// across its line to free space again on the side that is not free, median over the stations;
// infinity when the piece is free on both sides or behind it stays non-free beyond max_depth.
double depthBehind(const Piece& p, double max_depth, const Context& ctx) {
  const double res = ctx.grid.resolution;
  const Vec2 n = p.normal();
  const double half = 0.5 * std::max(p.thickness, res);
  const int stations = std::clamp(static_cast<int>(p.length() / (2 * res)), 3, 24);
  int front_pos = 0, front_neg = 0;
  for (int k = 0; k < stations; ++k) {
    const Vec2 q = p.c + (p.t0 + (p.t1 - p.t0) * (k + 0.5) / stations) * p.d;
    for (int depth = 1; depth <= 2; ++depth) {
      front_pos += ctx.isFree(q + (half + depth * res) * n);
      front_neg += ctx.isFree(q - (half + depth * res) * n);
    }
  }
  if (std::min(front_pos, front_neg) > stations / 2) return std::numeric_limits<double>::infinity();  // two-sided
  const Vec2 back = front_pos >= front_neg ? Vec2(-n) : n;
  std::vector<double> depths;
  for (int k = 0; k < stations; ++k) {
    const Vec2 q = p.c + (p.t0 + (p.t1 - p.t0) * (k + 0.5) / stations) * p.d;
    double d = std::numeric_limits<double>::infinity();
    for (double s = res; s <= max_depth; s += 0.5 * res)
      if (ctx.isFree(q + s * back)) {
        d = s;
        break;
      }
    depths.push_back(d);
  }
  std::nth_element(depths.begin(), depths.begin() + static_cast<std::ptrdiff_t>(depths.size() / 2), depths.end());
  return depths[depths.size() / 2];
}

// True when, at most stations along p, one side's free space is a pocket smaller than a room: the
// inside of a piece of furniture drawn as an outline.
bool facesPocket(const Piece& p, const Components& free, double min_cells, const Context& ctx) {
  const double res = ctx.grid.resolution;
  const Vec2 n = p.normal();
  const double off = 0.5 * std::max(p.thickness, res) + 1.5 * res;
  const int stations = std::clamp(static_cast<int>(p.length() / (2 * res)), 3, 24);
  int pocket = 0;
  const auto small = [&](const Vec2& q) {
    const int x = static_cast<int>(std::floor(q.x() / res)), y = static_cast<int>(std::floor(q.y() / res));
    if (x < 0 || y < 0 || x >= ctx.grid.width || y >= ctx.grid.height) return false;
    const std::int32_t k = free.label[static_cast<std::size_t>(y) * ctx.grid.width + x];
    return k >= 0 && static_cast<double>(free.sizes[static_cast<std::size_t>(k)]) < min_cells;
  };
  for (int k = 0; k < stations; ++k) {
    const Vec2 q = p.c + (p.t0 + (p.t1 - p.t0) * (k + 0.5) / stations) * p.d;
    pocket += small(q + off * n) || small(q - off * n);
  }
  return 2 * pocket > stations;
}

}  // namespace

void separateClutter(std::vector<Piece> joined, const std::vector<std::size_t>& line_of,
                     const std::vector<WallLine>& lines, const std::vector<Piece>& glass, const Components& free,
                     const std::vector<Piece>& fitted, const Context& ctx, Structure& out) {
  const StructureOptions& o = ctx.opt.structure;
  const std::size_t n = joined.size();
  const double pocket_cells = o.min_room_area / (ctx.grid.resolution * ctx.grid.resolution);
  std::vector<char> wall(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const WallLine& l = lines[line_of[i]];
    wall[i] = l.direction >= 0 ? l.support >= o.min_line_support : joined[i].length() >= o.off_direction_min_length;
    if (wall[i] && facesPocket(joined[i], free, pocket_cells, ctx)) wall[i] = 0;
  }
  // Free space again a little behind a one-sided piece, deeper than a wall is thick: an object one
  // can walk around (a desk, a cabinet, a pillar), not a wall.
  for (std::size_t i = 0; i < n; ++i) {
    const Piece& p = joined[i];
    if (!wall[i] || p.faces_merged || p.length() >= o.max_furniture_length) continue;
    const double depth = depthBehind(p, o.furniture_depth, ctx);
    if (depth > ctx.wall_thickness + 2 * ctx.grid.resolution && depth <= o.furniture_depth) wall[i] = 0;
  }
  // In front of a longer parallel wall, close to it and overlapping it: furniture against it.
  std::vector<char> shadowed(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const Piece& p = joined[i];
    const WallLine& l = lines[line_of[i]];
    if (p.length() >= o.max_furniture_length) continue;
    for (std::size_t j = 0; j < n && !shadowed[i]; ++j) {
      const WallLine& m = lines[line_of[j]];
      if (j == i || !wall[j] || line_of[j] == line_of[i] || m.support < 2.0 * l.support) continue;
      if (std::abs(p.d.dot(joined[j].d)) < std::cos(deg2rad(3.0))) continue;
      const double sep = std::abs(joined[j].normal().dot(0.5 * (p.a() + p.b()) - joined[j].c));
      if (sep < o.line_tolerance || sep > o.shadow_depth) continue;
      shadowed[i] = overlapAlong(p, joined[j]) >= 0.5 * p.length();
    }
  }
  for (std::size_t i = 0; i < n; ++i)
    if (shadowed[i]) wall[i] = 0;
  // Pieces joining walls (or panes) at both ends are walls too, found outward from the walls. A
  // pane's line counts as far as snapCorners moves its end onto a wall.
  const double pane_reach = ctx.glassCornerSnap() - ctx.opt.corner_snap;
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t i = 0; i < n; ++i) {
      if (wall[i] || shadowed[i]) continue;
      const Piece& p = joined[i];
      bool at_a = false, at_b = false;
      const auto check = [&](const Piece& q, double beyond) {
        at_a = at_a || meets(p, p.a(), q, ctx, beyond);
        at_b = at_b || meets(p, p.b(), q, ctx, beyond);
      };
      for (std::size_t j = 0; j < n; ++j)
        if (j != i && wall[j]) check(joined[j], 0.0);
      for (const Piece& g : glass) check(g, pane_reach);
      if (at_a && at_b) wall[i] = 1, changed = true;
    }
  }
  // Openings count between two walls of the building only (not between pieces of furniture), and
  // not where another wall crosses the gap: a line running on across a corridor is a junction.
  const auto crossed = [&](const Opening& op) {
    const Vec2 u = (op.b - op.a).normalized();
    const auto crosses = [&](const Piece& q) {
      if (std::abs(u.dot(q.d)) > std::cos(deg2rad(ctx.opt.corner_min_angle_deg))) return false;
      const double reach = 0.5 * q.thickness + 2 * ctx.grid.resolution;
      const Vec2 a = op.a - reach * u, b = op.b + reach * u;
      // Segment a..b against q's extent: the two ends on opposite sides of each other's line.
      const Vec2 qa = q.a(), qb = q.b();
      const auto side = [](const Vec2& o, const Vec2& d, const Vec2& p) {
        return d.x() * (p.y() - o.y()) - d.y() * (p.x() - o.x());
      };
      return side(a, b - a, qa) * side(a, b - a, qb) <= 0 && side(qa, qb - qa, a) * side(qa, qb - qa, b) <= 0;
    };
    for (std::size_t j = 0; j < n; ++j)
      if (wall[j] && crosses(joined[j])) return true;
    for (const Piece& g : glass)
      if (crosses(g)) return true;
    return false;
  };
  out.openings.erase(
      std::remove_if(out.openings.begin(), out.openings.end(),
                     [&](const Opening& op) { return !wall[op.left] || !wall[op.right] || crossed(op); }),
      out.openings.end());
  // Walls as joined; clutter as it was fitted (furniture is not aligned with the building: no
  // snapping to its directions, no joining along its lines).
  for (std::size_t i = 0; i < n; ++i) {
    if (wall[i]) {
      out.walls.push_back(std::move(joined[i]));
      continue;
    }
    for (const std::uint32_t k : joined[i].parts) out.clutter.push_back(fitted[k]);
  }
}

Structure extractStructure(std::vector<Piece> walls, const std::vector<Piece>& glass, const CellCloud& cloud,
                           const Context& ctx) {
  Structure out;
  out.directions = dominantDirections(walls, glass, ctx);
  const std::vector<Piece> fitted = walls;
  const std::vector<int> which = snapToDirections(walls, out.directions, ctx);
  for (const int w : which) out.snapped += w >= 0;
  const std::vector<WallLine> lines = groupLines(walls, which, out.directions, ctx);
  std::vector<std::size_t> line_of;
  std::vector<Piece> joined = joinLines(lines, walls, glass, cloud, ctx, line_of, out);
  std::vector<std::uint8_t> is_free(ctx.grid.cells());
  for (std::size_t i = 0; i < is_free.size(); ++i) is_free[i] = ctx.grid.codes[i] == kCodeEmpty;
  Components free = connectedComponents(ctx.grid.width, ctx.grid.height, is_free);
  // Only a pocket sealed by what was hit all round is the inside of a drawn outline; one that
  // touches unknown cells is free space not seen whole (real maps have many). Unsealed pockets
  // count as large.
  const int w = ctx.grid.width, h = ctx.grid.height;
  std::vector<char> sealed(free.count(), 1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::int32_t k = free.label[static_cast<std::size_t>(y) * w + x];
      if (k < 0) continue;
      for (const auto& [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
        const int nx = x + dx, ny = y + dy;
        if (nx < 0 || ny < 0 || nx >= w || ny >= h || ctx.grid.code(nx, ny) == kCodeUnknown)
          sealed[static_cast<std::size_t>(k)] = 0;
      }
    }
  for (std::size_t k = 0; k < free.count(); ++k)
    if (!sealed[k]) free.sizes[k] = std::numeric_limits<std::size_t>::max();
  separateClutter(std::move(joined), line_of, lines, glass, free, fitted, ctx, out);
  return out;
}

}  // namespace glassmap::vector::detail
