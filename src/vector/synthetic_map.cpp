// Test maps of a true floorplan with furniture, in three conventions (see synthetic_map.hpp).
#include "glassmap/vector/synthetic_map.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>

#include "glassmap/core/angles.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/core/split_mix.hpp"
#include "glassmap/geometry/ray_caster.hpp"
#include "glassmap/grid/distance_transform.hpp"
#include "grid_util.hpp"

namespace glassmap::vector {

std::string toString(MapConvention c) {
  switch (c) {
    case MapConvention::Solid: return "solid";
    case MapConvention::Slam: return "slam";
    case MapConvention::Drawn: return "drawn";
  }
  return "solid";
}

MapConvention parseMapConvention(const std::string& name, const std::string& field) {
  if (name == "solid") return MapConvention::Solid;
  if (name == "slam") return MapConvention::Slam;
  if (name == "drawn") return MapConvention::Drawn;
  throw Error("unknown map convention '" + name + "' (expected solid, slam or drawn)", {}, 0, field);
}

namespace {

// A furniture piece: a rectangle centred at c with half sizes h along u and along u's normal.
struct Box {
  Vec2 c = Vec2::Zero();
  Vec2 u = Vec2::UnitX();
  Vec2 h = Vec2::Zero();
  Vec2 v() const { return {-u.y(), u.x()}; }
  Vec2 corner(int k) const {
    const double su = (k == 0 || k == 3) ? -1.0 : 1.0, sv = k < 2 ? -1.0 : 1.0;
    return c + su * h.x() * u + sv * h.y() * v();
  }
  bool contains(const Vec2& p, double grow) const {
    const Vec2 d = p - c;
    return std::abs(d.dot(u)) <= h.x() + grow && std::abs(d.dot(v())) <= h.y() + grow;
  }
};

// Calls f(cell index) for the cells whose centre lies in the box grown by `grow` [m].
template <typename F>
void forBoxCells(const LabelGrid& g, const Box& b, double grow, F&& f) {
  const double r = b.h.norm() + grow;
  const auto cell = [&](double v, double o) { return static_cast<int>(std::floor((v - o) / g.resolution)); };
  const int x0 = std::max(0, cell(b.c.x() - r, g.origin.x())), y0 = std::max(0, cell(b.c.y() - r, g.origin.y()));
  const int x1 = std::min(g.width - 1, cell(b.c.x() + r, g.origin.x()));
  const int y1 = std::min(g.height - 1, cell(b.c.y() + r, g.origin.y()));
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x)
      if (b.contains(g.center(x, y), grow)) f(static_cast<std::size_t>(y) * g.width + x);
}

// Free wall ends of the structure: door jambs and wall stubs (no other segment within 0.2 m).
std::vector<Vec2> freeEnds(const VectorMap& structure) {
  std::vector<Vec2> ends;
  for (std::size_t i = 0; i < structure.segments.size(); ++i)
    for (const Vec2& e : {structure.segments[i].a, structure.segments[i].b}) {
      bool joined = false;
      for (std::size_t j = 0; j < structure.segments.size() && !joined; ++j)
        joined = j != i && structure.segments[j].distanceTo(e) < 0.2;
      if (!joined) ends.push_back(e);
    }
  return ends;
}

// The building's inside: cells not occupied and not reached from the grid's border, where an
// entrance up to `entrance` [m] wide does not let the outside in (the walls grown by half of it
// stop the flood from the border; the outside then grows back to the walls); enclosed pockets
// under min_cells (a desk's inside) are not inside either. Returns 1 for inside cells.
std::vector<std::uint8_t> insideCells(const LabelGrid& g, std::size_t min_cells, double entrance) {
  const std::size_t n = g.cells();
  std::vector<std::uint8_t> wall(n), open(n);
  for (std::size_t i = 0; i < n; ++i) wall[i] = g.codes[i] == kCodeOccupied;
  const std::vector<float> to_wall = grid::distanceTransform(g.width, g.height, wall);
  const float r = static_cast<float>(0.5 * entrance / g.resolution);
  for (std::size_t i = 0; i < n; ++i) open[i] = to_wall[i] > r;
  const detail::Components c = detail::connectedComponents(g.width, g.height, open);
  std::vector<std::uint8_t> border(c.count(), 0);
  const auto mark = [&](int x, int y) {
    const std::int32_t k = c.label[static_cast<std::size_t>(y) * g.width + x];
    if (k >= 0) border[static_cast<std::size_t>(k)] = 1;
  };
  for (int x = 0; x < g.width; ++x) mark(x, 0), mark(x, g.height - 1);
  for (int y = 0; y < g.height; ++y) mark(0, y), mark(g.width - 1, y);
  std::vector<std::uint8_t> outside_seed(n, 0);
  for (std::size_t i = 0; i < n; ++i) outside_seed[i] = c.label[i] >= 0 && border[static_cast<std::size_t>(c.label[i])];
  for (int x = 0; x < g.width; ++x)  // the border itself (a margin narrower than the entrance)
    for (const int y : {0, g.height - 1})
      outside_seed[static_cast<std::size_t>(y) * g.width + x] |= !wall[static_cast<std::size_t>(y) * g.width + x];
  for (int y = 0; y < g.height; ++y)
    for (const int x : {0, g.width - 1})
      outside_seed[static_cast<std::size_t>(y) * g.width + x] |= !wall[static_cast<std::size_t>(y) * g.width + x];
  // The outside grows back to the walls through free cells only (8-neighbour steps, a chamfer
  // distance), as far as the walls were grown.
  std::vector<float> reach(n, std::numeric_limits<float>::infinity());
  std::deque<std::size_t> queue;
  for (std::size_t i = 0; i < n; ++i)
    if (outside_seed[i]) reach[i] = 0.0f, queue.push_back(i);
  while (!queue.empty()) {
    const std::size_t i = queue.front();
    queue.pop_front();
    const int x = static_cast<int>(i % static_cast<std::size_t>(g.width)),
              y = static_cast<int>(i / static_cast<std::size_t>(g.width));
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int nx = x + dx, ny = y + dy;
        if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= g.width || ny >= g.height) continue;
        const std::size_t j = static_cast<std::size_t>(ny) * g.width + nx;
        const float d = reach[i] + (dx != 0 && dy != 0 ? 1.4142f : 1.0f);
        if (wall[j] || d >= reach[j] || d > r + 1.5f) continue;
        reach[j] = d;
        queue.push_back(j);
      }
  }
  std::vector<std::uint8_t> candidate(n);
  for (std::size_t i = 0; i < n; ++i) candidate[i] = !wall[i] && !std::isfinite(reach[i]);
  const detail::Components in = detail::connectedComponents(g.width, g.height, candidate);
  std::vector<std::uint8_t> inside(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::int32_t k = in.label[i];
    inside[i] = k >= 0 && in.sizes[static_cast<std::size_t>(k)] >= min_cells;
  }
  return inside;
}

// Number of 4-connected components of inside cells within the window around a box.
std::size_t localComponents(const LabelGrid& g, const std::vector<std::uint8_t>& inside, const Box& b, double pad) {
  const double r = b.h.norm() + pad;
  const int x0 = std::max(0, static_cast<int>(std::floor((b.c.x() - r - g.origin.x()) / g.resolution)));
  const int y0 = std::max(0, static_cast<int>(std::floor((b.c.y() - r - g.origin.y()) / g.resolution)));
  const int x1 = std::min(g.width - 1, static_cast<int>(std::floor((b.c.x() + r - g.origin.x()) / g.resolution)));
  const int y1 = std::min(g.height - 1, static_cast<int>(std::floor((b.c.y() + r - g.origin.y()) / g.resolution)));
  const int w = x1 - x0 + 1, h = y1 - y0 + 1;
  if (w <= 0 || h <= 0) return 0;
  std::vector<std::uint8_t> win(static_cast<std::size_t>(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      win[static_cast<std::size_t>(y) * w + x] = inside[static_cast<std::size_t>(y + y0) * g.width + x + x0];
  const detail::Components c = detail::connectedComponents(w, h, win);
  return static_cast<std::size_t>(std::count_if(c.sizes.begin(), c.sizes.end(), [](std::size_t s) { return s > 4; }));
}

// Furniture placed in the inside cells until it covers the share asked for; bins after it.
void addFurniture(LabelGrid& g, std::vector<std::uint8_t>& inside, const VectorMap& structure,
                  const SyntheticMapOptions& o, SplitMix& rng, SyntheticMap& out) {
  std::vector<std::size_t> cells;
  for (std::size_t i = 0; i < g.cells(); ++i)
    if (inside[i]) cells.push_back(i);
  if (cells.empty() || structure.segments.empty()) return;
  const double area = static_cast<double>(cells.size()) * g.resolution * g.resolution;
  const std::vector<Vec2> jambs = freeEnds(structure);
  std::vector<double> cumulative;  // wall length, to pick a wall to stand against
  for (const MapSegment& s : structure.segments)
    cumulative.push_back((cumulative.empty() ? 0 : cumulative.back()) + s.length());
  const auto place = [&](const Box& b) {
    // Every cell under the piece inside, clear of door jambs, and the free space around it not cut.
    bool ok = true;
    forBoxCells(g, b, -0.5 * g.resolution, [&](std::size_t i) { ok = ok && inside[i]; });
    for (const Vec2& j : jambs) ok = ok && !b.contains(j, o.door_clearance);
    if (!ok) return false;
    const std::size_t before = localComponents(g, inside, b, 1.0);
    std::vector<std::size_t> under;
    forBoxCells(g, b, 0.0, [&](std::size_t i) { under.push_back(i); });
    for (const std::size_t i : under) inside[i] = 0;
    if (localComponents(g, inside, b, 1.0) > before) {
      for (const std::size_t i : under) inside[i] = 1;
      return false;
    }
    for (const std::size_t i : under) g.codes[i] = kCodeOccupied;
    for (int k = 0; k < 4; ++k) out.furniture.add(b.corner(k), b.corner((k + 1) % 4), Material::Wall).thickness = 0.02;
    ++out.pieces;
    return true;
  };
  double covered = 0.0;
  for (int attempt = 0; attempt < 200000 && covered < o.furniture_cover * area; ++attempt) {
    const double kind = rng.uniform();
    Box b;
    bool against = rng.uniform() < o.against_wall_share;
    if (kind < 0.45) {
      b.h = 0.5 * Vec2(rng.uniform(1.2, 2.0), rng.uniform(0.6, 0.9));  // desks, tables
    } else if (kind < 0.7) {
      b.h = 0.5 * Vec2(rng.uniform(0.8, 2.4), rng.uniform(0.35, 0.6));  // shelves, cabinets
      against = true;
    } else {
      b.h = 0.5 * Vec2(rng.uniform(0.4, 0.7), rng.uniform(0.4, 0.7));  // chairs, boxes
    }
    if (against) {
      const double pick = rng.uniform(0.0, cumulative.back());
      const auto k =
          static_cast<std::size_t>(std::lower_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin());
      const MapSegment& s = structure.segments[std::min(k, structure.segments.size() - 1)];
      if (s.length() < 2.0 * b.h.x()) continue;
      b.u = s.direction();
      const double along = rng.uniform(b.h.x(), s.length() - b.h.x());
      const double side = rng.uniform() < 0.5 ? 1.0 : -1.0;
      b.c = s.a + along * b.u + side * (0.5 * s.thickness + b.h.y() + 0.5 * g.resolution) * b.v();
    } else {
      const std::size_t i = cells[static_cast<std::size_t>(rng.uniform() * static_cast<double>(cells.size()))];
      b.c = g.center(static_cast<int>(i % g.width), static_cast<int>(i / g.width));
      const MapSegment& s = structure.segments[static_cast<std::size_t>(rng.uniform() * structure.segments.size())];
      const double a = rng.uniform() < 0.8 ? std::atan2(s.b.y() - s.a.y(), s.b.x() - s.a.x()) : rng.uniform(0.0, kPi);
      b.u = Vec2(std::cos(a), std::sin(a));
    }
    if (place(b)) covered += 4.0 * b.h.x() * b.h.y();
  }
  const auto bins = static_cast<std::size_t>(std::lround(o.bins_per_100m2 * area / 100.0));
  for (std::size_t placed = 0, attempt = 0; placed < bins && attempt < 100 * bins + 100; ++attempt) {
    Box b;
    const std::size_t i = cells[static_cast<std::size_t>(rng.uniform() * static_cast<double>(cells.size()))];
    b.c = g.center(static_cast<int>(i % g.width), static_cast<int>(i / g.width));
    const double a = rng.uniform(0.0, kPi), side = rng.uniform(0.25, 0.45);
    b.u = Vec2(std::cos(a), std::sin(a));
    b.h = Vec2(0.5 * side, 0.5 * side);
    placed += place(b);
  }
}

// Obstacles as a ray caster sees them: walls as their outlines (thickness), furniture outlines.
VectorMap obstacleOutlines(const VectorMap& structure, const VectorMap& thin, const VectorMap& furniture,
                           double min_t) {
  VectorMap m;
  for (const VectorMap* src : {&structure, &thin}) {
    for (const MapSegment& s : src->segments) {
      if (s.length() <= 0) continue;
      Box b;
      b.c = 0.5 * (s.a + s.b);
      b.u = s.direction();
      b.h = Vec2(0.5 * s.length() + 0.5 * std::max(s.thickness, min_t), 0.5 * std::max(s.thickness, min_t));
      for (int k = 0; k < 4; ++k) m.add(b.corner(k), b.corner((k + 1) % 4), Material::Wall);
    }
  }
  for (const MapSegment& s : furniture.segments) m.add(s.a, s.b, Material::Wall);
  return m;
}

// The slam convention: scans from viewpoints spread over the inside mark what they hit and clear
// what they cross; cells no beam touched stay unknown.
void scanMap(LabelGrid& g, const std::vector<std::uint8_t>& inside, const VectorMap& obstacles,
             const SyntheticMapOptions& o, SplitMix& rng, SyntheticMap& out) {
  std::vector<std::uint8_t> blocked(g.cells());
  for (std::size_t i = 0; i < g.cells(); ++i) blocked[i] = !inside[i];
  const std::vector<float> clearance = grid::distanceTransform(g.width, g.height, blocked);
  const RayCaster caster(obstacles);
  std::vector<std::uint32_t> hits(g.cells(), 0), misses(g.cells(), 0);
  const int stride = std::max(1, static_cast<int>(std::lround(o.viewpoint_spacing / g.resolution)));
  const int beams = static_cast<int>(std::lround(360.0 / o.beam_step_deg));
  const double step = deg2rad(360.0 / beams);
  for (int y = stride / 2; y < g.height; y += stride)
    for (int x = stride / 2; x < g.width; x += stride) {
      const std::size_t i = static_cast<std::size_t>(y) * g.width + x;
      if (!inside[i] || clearance[i] * g.resolution < o.viewpoint_clearance) continue;
      ++out.viewpoints;
      const Vec2 p = g.center(x, y) + g.resolution * Vec2(rng.uniform(-0.4, 0.4), rng.uniform(-0.4, 0.4));
      const double start = rng.uniform(0.0, step);
      for (int k = 0; k < beams; ++k) {
        const Vec2 dir(std::cos(start + k * step), std::sin(start + k * step));
        const double r = caster.castRange(p, dir, o.max_range);
        const bool hit = std::isfinite(r);
        const double reading = hit ? r + o.range_sigma * rng.normal() : o.max_range;
        const Vec2 from = (p - g.origin) / g.resolution, to = (p + reading * dir - g.origin) / g.resolution;
        const int ex = static_cast<int>(std::floor(to.x())), ey = static_cast<int>(std::floor(to.y()));
        detail::walkCells(from, to, g.width, g.height, [&](int cx, int cy) {
          const std::size_t c = static_cast<std::size_t>(cy) * g.width + cx;
          if (hit && cx == ex && cy == ey)
            ++hits[c];
          else
            ++misses[c];
          return true;
        });
      }
    }
  for (std::size_t i = 0; i < g.cells(); ++i)
    g.codes[i] = hits[i] > 0 && 2 * hits[i] >= misses[i] ? kCodeOccupied : misses[i] > 0 ? kCodeEmpty : kCodeUnknown;
}

}  // namespace

SyntheticMap makeSyntheticMap(const VectorMap& plan, const SyntheticMapOptions& o) {
  if (plan.segments.empty()) throw Error("the plan has no segments to draw a test map from");
  if (!(o.resolution > 0) || !(o.margin >= 0) || !(o.viewpoint_spacing > 0) || !(o.beam_step_deg > 0) ||
      !(o.max_range > 0) || o.furniture_cover < 0 || o.furniture_cover > 0.5)
    throw Error(
        "test map options out of range (resolution, spacing, beam step and range > 0, furniture cover in [0, 0.5])");
  SyntheticMap out;
  VectorMap thin;
  for (const MapSegment& s : plan.segments) {
    MapSegment w = s;
    w.material = Material::Wall;
    if (s.material == Material::Glass || s.thickness >= o.structure_thickness)
      out.structure.segments.push_back(w);
    else if (o.plan_furniture)
      thin.segments.push_back(w);
  }
  out.furniture = thin;
  const Eigen::AlignedBox2d box = plan.bounds();
  const Vec2 lo = box.min() - Vec2::Constant(o.margin), size = box.sizes() + Vec2::Constant(2 * o.margin);
  LabelGrid g = makeLabelGrid(static_cast<int>(std::ceil(size.x() / o.resolution)),
                              static_cast<int>(std::ceil(size.y() / o.resolution)), o.resolution, lo);
  std::fill(g.codes.begin(), g.codes.end(), kCodeEmpty);
  rasterize(g, out.structure, o.resolution);
  rasterize(g, thin, o.resolution);
  const auto min_cells = static_cast<std::size_t>(o.min_room_area / (o.resolution * o.resolution));
  std::vector<std::uint8_t> inside = insideCells(g, min_cells, o.entrance_width);
  SplitMix rng(o.seed);
  addFurniture(g, inside, out.structure, o, rng, out);
  switch (o.convention) {
    case MapConvention::Drawn: break;  // lines on white: as drawn
    case MapConvention::Solid:
      for (std::size_t i = 0; i < g.cells(); ++i) g.codes[i] = inside[i] ? kCodeEmpty : kCodeOccupied;
      break;
    case MapConvention::Slam: {
      VectorMap furniture_only;
      furniture_only.segments.assign(out.furniture.segments.begin() + static_cast<std::ptrdiff_t>(thin.segments.size()),
                                     out.furniture.segments.end());
      scanMap(g, inside, obstacleOutlines(out.structure, thin, furniture_only, o.resolution), o, rng, out);
      break;
    }
  }
  for (const std::uint8_t c : g.codes) out.free_area += c == kCodeEmpty;
  out.free_area *= o.resolution * o.resolution;
  out.grid = std::move(g);
  return out;
}

}  // namespace glassmap::vector
