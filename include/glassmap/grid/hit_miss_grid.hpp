#pragma once
/// Sparse per-cell hit/miss counters and the standard log-odds occupancy read from them.
///
/// Memory grows with what was observed: the grid is cut into 32 x 32-cell tiles allocated on first
/// touch (4 bytes per cell: uint16 hits + uint16 misses); untouched tiles cost one pointer.

#include <cstdint>
#include <memory>
#include <vector>

#include "glassmap/grid/grid_geometry.hpp"

namespace glassmap::grid {

/// Hit and miss counts of one cell (saturating at 65535).
struct CellCounts {
  std::uint16_t hits = 0;    ///< beams that ended in the cell
  std::uint16_t misses = 0;  ///< beams that crossed the cell without ending in it
};

/// Standard log-odds occupancy (binary Bayes filter, static world): l = hits * l_hit +
/// misses * l_miss, clamped to [l_min, l_max]. Summing counts then clamping once makes the map
/// independent of beam order. Defaults are OctoMap's (p_hit 0.7, p_miss 0.4, clamp 0.12 / 0.97).
struct OccupancyModel {
  double l_hit = 0.847;     ///< log-odds added by a hit (p = 0.7)
  double l_miss = -0.405;   ///< log-odds added by a miss (p = 0.4)
  double l_min = -1.992;    ///< lower clamp (p = 0.12)
  double l_max = 3.476;     ///< upper clamp (p = 0.97)
  double l_occupied = 0.0;  ///< a cell with l > l_occupied counts as occupied (p > 0.5)

  double logOdds(const CellCounts& c) const;
  double probability(const CellCounts& c) const;
  bool occupied(const CellCounts& c) const { return c.hits != 0 && logOdds(c) > l_occupied; }
  bool operator==(const OccupancyModel&) const = default;
};

/// Tiled sparse grid of CellCounts over a GridGeometry.
class HitMissGrid {
 public:
  static constexpr int kTileBits = 5;  ///< tiles of 32 x 32 cells
  static constexpr int kTileSize = 1 << kTileBits;
  static constexpr int kTileCells = kTileSize * kTileSize;

  explicit HitMissGrid(const GridGeometry& geometry);

  const GridGeometry& geometry() const { return geometry_; }

  /// Counts of cell (x, y), allocating its tile on first touch. (x, y) must be inside the grid.
  CellCounts& at(int x, int y) {
    auto& tile = tiles_[tileIndex(x, y)];
    if (!tile) tile = allocateTile();
    return tile[offset(x, y)];
  }
  /// Counts of cell (x, y); zero if never touched or outside the grid.
  CellCounts get(int x, int y) const {
    if (!geometry_.contains(x, y)) return {};
    const auto& tile = tiles_[tileIndex(x, y)];
    return tile ? tile[offset(x, y)] : CellCounts{};
  }
  void addHit(int x, int y) { bump(at(x, y).hits); }
  void addMiss(int x, int y) { bump(at(x, y).misses); }

  /// addHit/addMiss for a walk that visits neighbouring cells in turn: keeps the tile of the last
  /// cell, so a step within it looks up no tile. The grid must outlive the cursor.
  class Cursor {
   public:
    explicit Cursor(HitMissGrid& grid) : grid_(&grid) {}
    CellCounts& at(int x, int y) {
      const int tx = x >> kTileBits, ty = y >> kTileBits;
      if (tx != tx_ || ty != ty_) {
        auto& tile = grid_->tiles_[grid_->tileIndex(x, y)];
        if (!tile) tile = grid_->allocateTile();
        tile_ = tile.get();
        tx_ = tx;
        ty_ = ty;
      }
      return tile_[offset(x, y)];
    }
    void addHit(int x, int y) { bump(at(x, y).hits); }
    void addMiss(int x, int y) { bump(at(x, y).misses); }

   private:
    HitMissGrid* grid_;
    CellCounts* tile_ = nullptr;
    int tx_ = -1, ty_ = -1;
  };

  /// Adds other's counts (same geometry) cell by cell, saturating like addHit/addMiss: a grid
  /// filled in parts and merged equals one filled in one go, whatever the order.
  void merge(const HitMissGrid& other);
  /// The same, taking over other's tiles where this grid has none (no copy); other is left empty.
  void merge(HitMissGrid&& other);

  /// True if the tile holding (x, y) is allocated.
  bool tileAllocated(int x, int y) const { return static_cast<bool>(tiles_[tileIndex(x, y)]); }
  std::size_t allocatedTiles() const { return allocated_; }
  /// Cells with at least one hit or miss (counts every allocated tile; O(allocated cells)).
  std::size_t observedCells() const;
  /// Bytes held: tile table plus allocated tiles.
  std::size_t bytes() const;

 private:
  /// Saturating count: the grid's 16-bit counts stop at 65535.
  static void bump(std::uint16_t& n) {
    if (n != 0xFFFF) ++n;
  }
  /// Index of cell (x, y) inside its tile.
  static std::size_t offset(int x, int y) {
    return static_cast<std::size_t>(((y & (kTileSize - 1)) << kTileBits) | (x & (kTileSize - 1)));
  }
  std::size_t tileIndex(int x, int y) const {
    return static_cast<std::size_t>(y >> kTileBits) * tiles_x_ + static_cast<std::size_t>(x >> kTileBits);
  }
  std::unique_ptr<CellCounts[]> allocateTile();

  GridGeometry geometry_;
  std::size_t tiles_x_ = 0, tiles_y_ = 0;
  std::vector<std::unique_ptr<CellCounts[]>> tiles_;
  std::size_t allocated_ = 0;
};

}  // namespace glassmap::grid
