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

LabelGrid finish(LabelGrid g, const OccupancyOptions& o, OccupancyStats* stats) {
  OccupancyStats s;
  for (std::uint8_t c : g.codes) {
    s.free += c == kCodeEmpty;
    s.occupied += c == kCodeOccupied;
    s.unknown += c == kCodeUnknown;
  }
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
  return finish(std::move(g), options, stats);
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
  return finish(std::move(g), options, stats);
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
