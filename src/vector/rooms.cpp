// Structure step 4: rooms. The plan's walls, panes and openings (doors and every other gap a door
// wide or less, windows among them) close the free space into cells; each enclosed region of the
// map is a room (a room keeps the furniture standing in it), its outline traced along the cell
// edges and simplified (Douglas-Peucker). Regions touching the map's border are the outside.
#include <algorithm>
#include <cmath>
#include <map>

#include "grid_util.hpp"
#include "structure.hpp"

namespace glassmap::vector::detail {

namespace {

// Marks the cells within `half` [m] of segment a..b (at least the cells it passes through).
void drawSegment(std::vector<std::uint8_t>& mask, const LabelGrid& g, const Vec2& a, const Vec2& b, double half) {
  const double res = g.resolution;
  const Vec2 lo = a.cwiseMin(b) - Vec2::Constant(half + res), hi = a.cwiseMax(b) + Vec2::Constant(half + res);
  const int x0 = std::max(0, static_cast<int>(std::floor(lo.x() / res)));
  const int y0 = std::max(0, static_cast<int>(std::floor(lo.y() / res)));
  const int x1 = std::min(g.width - 1, static_cast<int>(std::floor(hi.x() / res)));
  const int y1 = std::min(g.height - 1, static_cast<int>(std::floor(hi.y() / res)));
  const Vec2 ab = b - a;
  const double len2 = std::max(ab.squaredNorm(), 1e-18);
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const Vec2 c((x + 0.5) * res, (y + 0.5) * res);
      const double t = std::clamp((c - a).dot(ab) / len2, 0.0, 1.0);
      const Vec2 d = (c - (a + t * ab)).cwiseAbs();
      if (d.norm() <= half || (d.x() <= 0.5 * res && d.y() <= 0.5 * res))
        mask[static_cast<std::size_t>(y) * g.width + x] = 1;
    }
}

// Distance from p to segment a..b.
double distance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

// Douglas-Peucker on an open polyline [first, last].
void simplify(const std::vector<Vec2>& pts, std::size_t first, std::size_t last, double tol, std::vector<char>& keep) {
  if (last <= first + 1) return;
  double worst = -1;
  std::size_t at = first;
  for (std::size_t i = first + 1; i < last; ++i) {
    const double d = distance(pts[i], pts[first], pts[last]);
    if (d > worst) worst = d, at = i;
  }
  if (worst <= tol) return;
  keep[at] = 1;
  simplify(pts, first, at, tol, keep);
  simplify(pts, at, last, tol, keep);
}

// The outer boundary of the cells of component k, along the cell edges, counter-clockwise.
std::vector<Vec2> outline(const Components& c, std::int32_t k, int w, int h, double res) {
  const auto in = [&](int x, int y) {
    return x >= 0 && y >= 0 && x < w && y < h && c.label[static_cast<std::size_t>(y) * w + x] == k;
  };
  // Directed edges with the inside on the left, keyed by their start corner (x, y).
  std::multimap<std::pair<int, int>, std::pair<int, int>> next;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (!in(x, y)) continue;
      if (!in(x, y - 1)) next.insert({{x, y}, {x + 1, y}});          // bottom, eastward
      if (!in(x + 1, y)) next.insert({{x + 1, y}, {x + 1, y + 1}});  // right, northward
      if (!in(x, y + 1)) next.insert({{x + 1, y + 1}, {x, y + 1}});  // top, westward
      if (!in(x - 1, y)) next.insert({{x, y + 1}, {x, y}});          // left, southward
    }
  std::vector<Vec2> best;
  double best_area = 0;
  while (!next.empty()) {
    std::vector<std::pair<int, int>> loop;
    auto it = next.begin();
    const std::pair<int, int> start = it->first;
    std::pair<int, int> at = start, dir{0, 0};
    do {
      // At a corner two loops touch (diagonal cells): take the left-most turn, keeping the loop
      // around this component's 4-connected cells.
      auto range = next.equal_range(at);
      auto pick = range.first;
      if (std::distance(range.first, range.second) > 1) {
        for (auto e = range.first; e != range.second; ++e) {
          const std::pair<int, int> d{e->second.first - at.first, e->second.second - at.second};
          if (d.first == -dir.second && d.second == dir.first) pick = e;  // a left turn
        }
      }
      loop.push_back(at);
      dir = {pick->second.first - at.first, pick->second.second - at.second};
      at = pick->second;
      next.erase(pick);
    } while (at != start && next.count(at) > 0);
    double area = 0;
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const auto& p = loop[i];
      const auto& q = loop[(i + 1) % loop.size()];
      area += 0.5 * (static_cast<double>(p.first) * q.second - static_cast<double>(q.first) * p.second);
    }
    if (area > best_area) {
      best_area = area;
      best.clear();
      for (const auto& p : loop) best.emplace_back(p.first * res, p.second * res);
    }
  }
  return best;
}

}  // namespace

std::vector<RoomPolygon> segmentRooms(const std::vector<Piece>& walls, const std::vector<Piece>& glass,
                                      const std::vector<Opening>& openings, const Context& ctx) {
  const LabelGrid& g = ctx.grid;
  const double res = g.resolution;
  std::vector<std::uint8_t> barrier(g.cells(), 0);
  for (const std::vector<Piece>* set : {&walls, &glass})
    for (const Piece& p : *set) drawSegment(barrier, g, p.a(), p.b(), 0.5 * std::max(p.thickness, 2 * res));
  for (const Opening& op : openings)
    if ((op.b - op.a).norm() <= ctx.opt.structure.door_max) drawSegment(barrier, g, op.a, op.b, res);
  std::vector<std::uint8_t> open(g.cells());
  for (std::size_t i = 0; i < g.cells(); ++i) open[i] = !barrier[i];
  const Components c = connectedComponents(g.width, g.height, open);
  std::vector<char> outside(c.count(), 0);
  std::vector<std::size_t> free_cells(c.count(), 0);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const std::int32_t k = c.label[static_cast<std::size_t>(y) * g.width + x];
      if (k < 0) continue;
      if (x == 0 || y == 0 || x == g.width - 1 || y == g.height - 1) outside[static_cast<std::size_t>(k)] = 1;
      free_cells[static_cast<std::size_t>(k)] += g.code(x, y) == kCodeEmpty;
    }
  std::vector<RoomPolygon> rooms;
  const double min_cells = ctx.opt.structure.min_room_area / (res * res);
  for (std::size_t k = 0; k < c.count(); ++k) {
    if (outside[k] || static_cast<double>(free_cells[k]) < min_cells) continue;
    const std::vector<Vec2> ring = outline(c, static_cast<std::int32_t>(k), g.width, g.height, res);
    if (ring.size() < 4) continue;
    // Simplified as a closed ring: split at the vertex farthest from the first.
    std::size_t far = 0;
    for (std::size_t i = 1; i < ring.size(); ++i)
      if ((ring[i] - ring[0]).squaredNorm() > (ring[far] - ring[0]).squaredNorm()) far = i;
    std::vector<Vec2> closed = ring;
    closed.push_back(ring[0]);
    std::vector<char> keep(closed.size(), 0);
    keep[0] = keep[far] = keep[closed.size() - 1] = 1;
    const double tol = std::max(1.5 * res, 0.5 * ctx.opt.structure.line_tolerance);
    simplify(closed, 0, far, tol, keep);
    simplify(closed, far, closed.size() - 1, tol, keep);
    RoomPolygon room;
    for (std::size_t i = 0; i + 1 < closed.size(); ++i)
      if (keep[i]) room.ring.push_back(closed[i]);
    if (room.ring.size() < 3) continue;
    for (std::size_t i = 0; i < room.ring.size(); ++i) {
      const Vec2& a = room.ring[i];
      const Vec2& b = room.ring[(i + 1) % room.ring.size()];
      room.area += 0.5 * (a.x() * b.y() - b.x() * a.y());
    }
    room.id = static_cast<int>(rooms.size()) + 1;
    rooms.push_back(std::move(room));
  }
  return rooms;
}

}  // namespace glassmap::vector::detail
