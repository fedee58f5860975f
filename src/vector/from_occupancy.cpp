#include "glassmap/vector/from_occupancy.hpp"

#include <algorithm>
#include <deque>

#include "glassmap/core/error.hpp"

namespace glassmap::vector {
namespace {

// Multi-source breadth-first search over the 8-neighbourhood from the cells marked 0 in `dist`
// (the rest -1), `rings` steps at most, into the cells `enter` admits.
template <class Enter>
void spread(const LabelGrid& g, std::vector<int>& dist, int rings, Enter&& enter) {
  std::deque<std::size_t> queue;
  for (std::size_t i = 0; i < dist.size(); ++i)
    if (dist[i] == 0) queue.push_back(i);
  while (!queue.empty()) {
    const std::size_t i = queue.front();
    queue.pop_front();
    if (dist[i] >= rings) continue;
    const int x = static_cast<int>(i % static_cast<std::size_t>(g.width));
    const int y = static_cast<int>(i / static_cast<std::size_t>(g.width));
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int nx = x + dx, ny = y + dy;
        if (nx < 0 || ny < 0 || nx >= g.width || ny >= g.height) continue;
        const std::size_t j = static_cast<std::size_t>(ny) * static_cast<std::size_t>(g.width) + nx;
        if (dist[j] >= 0 || !enter(j)) continue;
        dist[j] = dist[i] + 1;
        queue.push_back(j);
      }
  }
}

// Occupied cells with no free cell within `rings` 8-neighbour steps become unknown. Free space
// reaches first through up to `rim` unknown cells: the grey rim an image editor's anti-aliasing or
// a resampled map leaves between free space and a wall (read as unknown between the thresholds)
// would otherwise part every wall from free space, and every wall would be a solid area's inside.
std::size_t dropSolidInsides(LabelGrid& g, int rings, int rim) {
  if (rings < 0) return 0;
  const std::size_t n = g.cells();
  std::vector<int> dist(n, -1);
  for (std::size_t i = 0; i < n; ++i)
    if (g.codes[i] == kCodeEmpty) dist[i] = 0;
  if (rim > 0) {
    spread(g, dist, rim, [&](std::size_t j) { return g.codes[j] == kCodeUnknown; });
    for (int& d : dist) d = d >= 0 ? 0 : -1;  // the rim is free space's edge too
  }
  spread(g, dist, rings, [](std::size_t) { return true; });
  std::size_t dropped = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (g.codes[i] == kCodeOccupied && dist[i] < 0) {
      g.codes[i] = kCodeUnknown;
      ++dropped;
    }
  return dropped;
}

// OccupancyOptions::ridges: unknown cells darker than `level` and a peak of occupancy across a row,
// a column or a diagonal become occupied (all decided on the grid as read, none from another's).
// The level lies this share of the way from free_thresh to occupied_thresh: a one-cell band blurred
// at 1.5 px keeps about a third of its darkness, and unknown grey sits at free_thresh.
constexpr double kRidgeLevel = 0.25;
template <class Occupancy>
std::size_t occupyRidges(LabelGrid& g, Occupancy&& occ, double level) {
  const int w = g.width, h = g.height;
  std::vector<std::size_t> ridge;
  for (int y = 1; y + 1 < h; ++y)
    for (int x = 1; x + 1 < w; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x);
      const double o = occ(i);
      if (g.codes[i] != kCodeUnknown || !(o > level)) continue;
      for (const auto& [dx, dy] : {std::pair{1, 0}, std::pair{0, 1}, std::pair{1, 1}, std::pair{1, -1}}) {
        const std::ptrdiff_t step = static_cast<std::ptrdiff_t>(dy) * w + dx;
        const double a = occ(i - step), b = occ(i + step);
        if ((o > a && o >= b) || (o >= a && o > b)) {
          ridge.push_back(i);
          break;
        }
      }
    }
  for (const std::size_t i : ridge) g.codes[i] = kCodeOccupied;
  return ridge.size();
}

LabelGrid finish(LabelGrid g, const OccupancyOptions& o, OccupancyStats* stats, std::size_t ridges = 0) {
  OccupancyStats s;
  for (std::uint8_t c : g.codes) {
    s.free += c == kCodeEmpty;
    s.occupied += c == kCodeOccupied;
    s.unknown += c == kCodeUnknown;
  }
  s.ridges = ridges;
  s.solid_inside = dropSolidInsides(g, o.face_cells, o.rim_cells);
  if (stats) *stats = s;
  g.validate();
  return g;
}

}  // namespace

LabelGrid fromOccupancy(const OccupancyGridMap& map, const OccupancyOptions& options, OccupancyStats* stats) {
  if (map.width <= 0 || map.height <= 0 || map.data.size() != static_cast<std::size_t>(map.width) * map.height)
    throw Error("occupancy grid size does not match its data");
  LabelGrid g = makeLabelGrid(map.width, map.height, map.resolution, Vec2::Zero());
  for (std::size_t i = 0; i < map.data.size(); ++i) {
    const int v = map.data[i];
    g.codes[i] = v == 0 ? kCodeEmpty : v == 100 ? kCodeOccupied : kCodeUnknown;
  }
  std::size_t ridges = 0;
  if (options.ridges && map.occupancy.size() == map.data.size())
    ridges = occupyRidges(
        g, [&](std::size_t i) { return static_cast<double>(map.occupancy[i]); },
        map.free_thresh + kRidgeLevel * (map.occupied_thresh - map.free_thresh));
  return finish(std::move(g), options, stats, ridges);
}

LabelGrid fromOccupancyRaster(const LabelRaster& pixels, double occupied_thresh, double free_thresh,
                              const OccupancyOptions& options, OccupancyStats* stats) {
  if (!(free_thresh >= 0 && free_thresh < occupied_thresh && occupied_thresh <= 1))
    throw Error("expected 0 <= free_thresh < occupied_thresh <= 1", {}, 0, "occupied_thresh/free_thresh");
  LabelGrid g = makeLabelGrid(pixels.width, pixels.height, pixels.resolution, pixels.origin);
  for (std::size_t i = 0; i < pixels.codes.size(); ++i) {
    const double occ = (255.0 - pixels.codes[i]) / 255.0;
    g.codes[i] = occ > occupied_thresh ? kCodeOccupied : occ < free_thresh ? kCodeEmpty : kCodeUnknown;
  }
  std::size_t ridges = 0;
  if (options.ridges)
    ridges = occupyRidges(
        g, [&](std::size_t i) { return (255.0 - pixels.codes[i]) / 255.0; },
        free_thresh + kRidgeLevel * (occupied_thresh - free_thresh));
  return finish(std::move(g), options, stats, ridges);
}

bool looksLikeLabelCodes(const LabelRaster& raster, int bins) {
  return std::all_of(raster.codes.begin(), raster.codes.end(), [&](std::uint8_t c) {
    return c < kCodeFirstGlass || (c >= kCodeFirstGlass && c < kCodeFirstGlass + bins);
  });
}

VectorMap placeOnPose(VectorMap map, const Pose2& origin) {
  for (MapSegment& s : map.segments) {
    s.a = origin * s.a;
    s.b = origin * s.b;
  }
  return map;
}

}  // namespace glassmap::vector
