#pragma once
/// Per-cell hits and misses per incidence-angle bin, kept only for candidate cells (cells some
/// beam ended in): a full histogram (2 x bins uint16) for a small fraction of the observed cells.
///
/// Bin b holds beams whose direction, modulo 180 deg, is within half a bin of b * bin_width
/// (a pane and its back face are one line, so 180 deg wraps to bin 0).

#include <cstdint>
#include <memory>
#include <vector>

#include "glassmap/grid/hit_miss_grid.hpp"

namespace glassmap::grid {

/// Bin of a beam direction [rad] for `bins` bins over [0, 180) deg, bin b centred on b * 180/bins.
inline int angleBin(double beam_angle, int bins) {
  const double half_turn = wrapHalfTurn(beam_angle);
  int b = static_cast<int>(std::lround(half_turn * bins / kPi));
  return b >= bins ? b - bins : b;
}

/// Candidate cells and their per-angle histograms.
class AngleHistograms {
 public:
  static constexpr std::int32_t kNone = -1;

  /// Candidates = cells of `counts` with at least min_hits hits; histograms start at zero.
  AngleHistograms(const HitMissGrid& counts, int bins, int min_hits = 1);

  const GridGeometry& geometry() const { return geometry_; }
  int bins() const { return bins_; }
  std::size_t size() const { return cells_.size(); }

  /// Candidate id of cell (x, y) inside the grid, or kNone.
  std::int32_t find(int x, int y) const {
    const auto& tile = tiles_[tileIndex(x, y)];
    if (!tile) return kNone;
    return tile[((y & (kTileSize - 1)) << kTileBits) | (x & (kTileSize - 1))];
  }
  /// find() for a walk that visits neighbouring cells in turn: keeps the index tile of the last
  /// cell (a step within it looks up no tile). The histograms must outlive the cursor.
  class Cursor {
   public:
    explicit Cursor(const AngleHistograms& h) : h_(&h) {}
    std::int32_t find(int x, int y) {
      const int tx = x >> kTileBits, ty = y >> kTileBits;
      if (tx != tx_ || ty != ty_) {
        tile_ = h_->tiles_[h_->tileIndex(x, y)].get();
        tx_ = tx;
        ty_ = ty;
      }
      if (!tile_) return kNone;
      return tile_[((y & (kTileSize - 1)) << kTileBits) | (x & (kTileSize - 1))];
    }

   private:
    const AngleHistograms* h_;
    const std::int32_t* tile_ = nullptr;
    int tx_ = -1, ty_ = -1;
  };

  /// Linear cell index (GridGeometry::index) of candidate id.
  std::uint32_t cell(std::int32_t id) const { return cells_[static_cast<std::size_t>(id)]; }
  /// Hits of candidate id per bin (bins() values).
  std::uint16_t* hits(std::int32_t id) { return &counts_[static_cast<std::size_t>(id) * 2 * bins_]; }
  const std::uint16_t* hits(std::int32_t id) const { return &counts_[static_cast<std::size_t>(id) * 2 * bins_]; }
  /// Misses of candidate id per bin (bins() values).
  std::uint16_t* misses(std::int32_t id) { return hits(id) + bins_; }
  const std::uint16_t* misses(std::int32_t id) const { return hits(id) + bins_; }

  void addHit(std::int32_t id, int bin) {
    auto& c = hits(id)[bin];
    if (c != 0xFFFF) ++c;
  }
  void addMiss(std::int32_t id, int bin) {
    auto& c = misses(id)[bin];
    if (c != 0xFFFF) ++c;
  }

  /// Counts for one thread of a parallel pass: a zeroed array shaped like this one's histograms,
  /// filled with addHit/addMiss(counts, ...) and added back with merge(). Saturating throughout,
  /// so the merged histograms equal a serial pass whatever the split.
  std::vector<std::uint16_t> emptyCounts() const { return std::vector<std::uint16_t>(counts_.size(), 0); }
  void addHit(std::vector<std::uint16_t>& counts, std::int32_t id, int bin) const {
    auto& c = counts[static_cast<std::size_t>(id) * 2 * bins_ + static_cast<std::size_t>(bin)];
    if (c != 0xFFFF) ++c;
  }
  void addMiss(std::vector<std::uint16_t>& counts, std::int32_t id, int bin) const {
    auto& c = counts[static_cast<std::size_t>(id) * 2 * bins_ + static_cast<std::size_t>(bins_ + bin)];
    if (c != 0xFFFF) ++c;
  }
  void merge(const std::vector<std::uint16_t>& counts);

  /// Bytes held (index tiles, cell list, histograms).
  std::size_t bytes() const;

 private:
  static constexpr int kTileBits = HitMissGrid::kTileBits;
  static constexpr int kTileSize = HitMissGrid::kTileSize;
  std::size_t tileIndex(int x, int y) const {
    return static_cast<std::size_t>(y >> kTileBits) * tiles_x_ + static_cast<std::size_t>(x >> kTileBits);
  }

  GridGeometry geometry_;
  int bins_ = 36;
  std::size_t tiles_x_ = 0;
  std::vector<std::unique_ptr<std::int32_t[]>> tiles_;  // only tiles holding candidates
  std::vector<std::uint32_t> cells_;
  std::vector<std::uint16_t> counts_;  // per candidate: hits[bins], misses[bins]
};

}  // namespace glassmap::grid
