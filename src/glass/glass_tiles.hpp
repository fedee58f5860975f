#pragma once
/// Coarse tiles of a grid that hold marked cells (glass, say), grown by one tile: a beam whose walk
/// over the tiles meets none of them crosses no marked cell, and most beams of a floor never do;
/// and an index of candidate cells by tile.

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

#include "glassmap/core/labels.hpp"
#include "glassmap/glass/evidence.hpp"
#include "glassmap/grid/traversal.hpp"

namespace glassmap::glass::detail {

/// The grid of tiles of `tile` x `tile` cells over g.
inline grid::GridGeometry coarseGrid(const grid::GridGeometry& g, int tile) {
  grid::GridGeometry c;
  c.resolution = g.resolution * tile;
  c.origin = g.origin;
  c.width = (g.width + tile - 1) / tile;
  c.height = (g.height + tile - 1) / tile;
  return c;
}

/// Walks segment a -> b over the tiles of `coarse` until marked(x, y); true when one is met. Tiles
/// are marked around their marked cells' own (grown by a tile), so a fine walk started one fine cell
/// (of `fine_resolution`) before that tile's entry meets every marked cell on the segment and every
/// cell within a tile of one: `from` (when given) is that start, as traverse's t_from.
template <class Marked>
bool firstTile(const grid::GridGeometry& coarse, double fine_resolution, const Vec2& a, const Vec2& b, Marked&& marked,
               double* from) {
  double entry = 0.0;
  bool found = false;
  grid::traverse(coarse, a, b, [&](int x, int y, double t, bool) {
    found = marked(x, y);
    entry = t;
    return !found;
  });
  if (found && from) {
    const double length = (b - a).norm();
    *from = length > 0.0 ? std::max(0.0, entry - fine_resolution / length) : 0.0;
  }
  return found;
}

/// Coarse tiles of `tile` x `tile` cells that hold a marked cell, grown by one tile (the coarse walk
/// of a segment and its fine walk may round a corner differently): a segment whose walk over the
/// tiles meets none of them crosses no marked cell.
class MarkedTiles {
 public:
  MarkedTiles(const grid::GridGeometry& g, int tile) : tile_(tile), coarse_(coarseGrid(g, tile)) {
    marked_.assign(coarse_.cells(), 0);
  }
  /// Marks fine cell (x, y) inside the grid.
  void mark(int x, int y) {
    for (int ty = y / tile_ - 1; ty <= y / tile_ + 1; ++ty)
      for (int tx = x / tile_ - 1; tx <= x / tile_ + 1; ++tx)
        if (coarse_.contains(tx, ty)) marked_[coarse_.index(tx, ty)] = 1;
  }
  /// True when segment a -> b passes a tile that holds a marked cell (or its neighbour); then
  /// `from` (when given) is where a fine walk of the segment may start and meet every marked cell
  /// on it (firstTile).
  bool near(const Vec2& a, const Vec2& b, double* from = nullptr) const {
    return firstTile(
        coarse_, coarse_.resolution / tile_, a, b, [&](int x, int y) { return marked_[coarse_.index(x, y)] != 0; },
        from);
  }
  /// The walk of segment a -> b over the tiles in runs of marked ones: run(t_in, t_out) per run, in
  /// order, t_in where the walk enters its first tile, t_out where it leaves its last (infinity when
  /// the run reaches the segment's end).
  template <class Run>
  void forEachRun(const Vec2& a, const Vec2& b, Run&& run) const {
    double t_in = -1.0;  // < 0: not in a run
    grid::traverse(coarse_, a, b, [&](int x, int y, double t, bool) {
      const bool marked = marked_[coarse_.index(x, y)] != 0;
      if (marked && t_in < 0.0) t_in = t;
      if (!marked && t_in >= 0.0) {
        run(t_in, t);
        t_in = -1.0;
      }
    });
    if (t_in >= 0.0) run(t_in, std::numeric_limits<double>::infinity());
  }

 private:
  int tile_;
  grid::GridGeometry coarse_;
  std::vector<std::uint8_t> marked_;
};

/// Calls visit(x, y, t_enter, last) as traverse(g, a, b, visit) would for every cell of segment
/// a -> b that is marked in `tiles` or next to a marked cell, in order and once each, walking the fine
/// cells only in the runs of marked tiles (from one fine cell before a run's first tile to where it
/// leaves its last): a pass that reads only marked cells skips the open space between them. A few
/// other cells near the runs' ends are visited too; t_enter of a run's first cell is where its walk
/// starts. Returns the cells visited.
template <class Visit>
std::size_t traverseMarked(const grid::GridGeometry& g, const MarkedTiles& tiles, const Vec2& a, const Vec2& b,
                           Visit&& visit) {
  const double length = (b - a).norm();
  const double back = length > 0.0 ? g.resolution / length : 0.0;
  std::size_t visited = 0;
  double resume = 0.0;  // where the last run's walk stopped: the first cell it did not visit
  grid::CellIndex previous{-1, -1};
  tiles.forEachRun(a, b, [&](double t_in, double t_out) {
    bool first = true;
    grid::traverse(
        g, a, b,
        [&](int x, int y, double t, bool last) {
          if (t >= t_out) {
            resume = t;
            return false;
          }
          // A walk resumed on a cell border may round into the cell the last run ended in.
          const bool again = first && x == previous.x && y == previous.y;
          first = false;
          if (again) return true;
          previous = {x, y};
          ++visited;
          visit(x, y, t, last);
          return true;
        },
        std::max(resume, t_in - back));
  });
  return visited;
}

/// Tiles of 2 x 2 cells that hold glass: a beam whose walk over them meets none cannot cross a
/// pane, and most beams of a floor never do.
class GlassTiles {
 public:
  explicit GlassTiles(const CellEvidence& e) : tiles_(e.geometry, 2) {
    const grid::GridGeometry& g = e.geometry;
    for (int y = 0; y < g.height; ++y)
      for (int x = 0; x < g.width; ++x)
        if (isGlass(e.label[g.index(x, y)])) tiles_.mark(x, y);
  }
  /// True when segment a -> b passes a tile that holds glass (or its neighbour); `from` as
  /// MarkedTiles::near's.
  bool near(const Vec2& a, const Vec2& b, double* from = nullptr) const { return tiles_.near(a, b, from); }

 private:
  MarkedTiles tiles_;
};

/// CellEvidence::candidate without its binary search: candidate numbers in tiles of 32 x 32 cells,
/// allocated only where candidates lie (a pass that looks up the end cell of every beam).
class CandidateIndex {
 public:
  explicit CandidateIndex(const CellEvidence& e) : CandidateIndex(e.geometry, e.cells) {}
  /// The index of any ascending list of linear cell indices: cell cells[i] finds i.
  template <class Index>
  CandidateIndex(const grid::GridGeometry& g, const std::vector<Index>& cells) : g_(g) {
    tiles_x_ = (static_cast<std::size_t>(g_.width) + kSize - 1) / kSize;
    tiles_.resize(tiles_x_ * ((static_cast<std::size_t>(g_.height) + kSize - 1) / kSize));
    for (std::size_t i = 0; i < cells.size(); ++i) {
      const grid::CellIndex c = g_.cellOf(cells[i]);
      auto& tile = tiles_[tileIndex(c.x, c.y)];
      if (tile.empty()) tile.assign(kSize * kSize, -1);
      tile[offset(c.x, c.y)] = static_cast<std::int32_t>(i);
    }
  }
  /// Candidate number of cell (x, y) inside the grid, or -1 (as CellEvidence::candidate).
  std::int64_t find(int x, int y) const {
    const auto& tile = tiles_[tileIndex(x, y)];
    return tile.empty() ? -1 : tile[offset(x, y)];
  }

 private:
  static constexpr int kBits = 5, kSize = 1 << kBits;
  std::size_t tileIndex(int x, int y) const {
    return static_cast<std::size_t>(y >> kBits) * tiles_x_ + static_cast<std::size_t>(x >> kBits);
  }
  static std::size_t offset(int x, int y) {
    return static_cast<std::size_t>(((y & (kSize - 1)) << kBits) | (x & (kSize - 1)));
  }
  grid::GridGeometry g_;
  std::size_t tiles_x_ = 0;
  std::vector<std::vector<std::int32_t>> tiles_;  // candidate numbers below 2^31 (cells of one grid)
};

}  // namespace glassmap::glass::detail
