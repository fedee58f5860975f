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

  /// Candidate id of cell (x, y) inside the grid, or kNone. A bit per cell answers first (a walk
  /// meets far more other cells than candidates, and the bits stay in cache where the ids do not).
  std::int32_t find(int x, int y) const {
    const std::size_t tile = tileIndex(x, y);
    const std::size_t bit = (tile << (2 * kTileBits)) | tileOffset(x, y);
    if (!((candidate_bits_[bit >> 6] >> (bit & 63)) & 1U)) return kNone;
    return tiles_[tile][tileOffset(x, y)];
  }
  /// find() for a walk that visits neighbouring cells in turn: keeps the index tile of the last
  /// cell (a step within it looks up no tile). The histograms must outlive the cursor.
  class Cursor {
   public:
    explicit Cursor(const AngleHistograms& h) : h_(&h) {}
    std::int32_t find(int x, int y) {
      const int tx = x >> kTileBits, ty = y >> kTileBits;
      if (tx != tx_ || ty != ty_) {
        const std::size_t tile = h_->tileIndex(x, y);
        tile_ = h_->tiles_[tile].get();
        bits_ = tile_ ? &h_->candidate_bits_[tile << (2 * kTileBits - 6)] : nullptr;
        tx_ = tx;
        ty_ = ty;
      }
      if (!tile_) return kNone;
      const std::size_t offset = tileOffset(x, y);
      if (!((bits_[offset >> 6] >> (offset & 63)) & 1U)) return kNone;
      return tile_[offset];
    }

   private:
    const AngleHistograms* h_;
    const std::int32_t* tile_ = nullptr;
    const std::uint64_t* bits_ = nullptr;  // the tile's candidate bits
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

  /// Counts for one thread of a parallel pass: a zeroed array of a histogram's size, filled with
  /// addHit/addMiss(counts, ...) and added back with merge(). Saturating throughout, so the merged
  /// histograms equal a serial pass whatever the split. Bin by bin (countsIndex), unlike the
  /// histograms: the beams of a scan that follow each other share a bin, so a pass works in one
  /// bin's counts of every candidate (2 bytes each) at a time rather than across all of memory.
  std::vector<std::uint16_t> emptyCounts() const { return std::vector<std::uint16_t>(counts_.size(), 0); }
  /// Where an emptyCounts() array keeps the hits (or misses) of candidate id in bin `bin`.
  std::size_t countsIndex(std::int32_t id, int bin, bool miss) const {
    return static_cast<std::size_t>(miss ? bins_ + bin : bin) * cells_.size() + static_cast<std::size_t>(id);
  }
  void addHit(std::vector<std::uint16_t>& counts, std::int32_t id, int bin) const {
    auto& c = counts[countsIndex(id, bin, false)];
    if (c != 0xFFFF) ++c;
  }
  void addMiss(std::vector<std::uint16_t>& counts, std::int32_t id, int bin) const {
    auto& c = counts[countsIndex(id, bin, true)];
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
  static std::size_t tileOffset(int x, int y) {
    return static_cast<std::size_t>(((y & (kTileSize - 1)) << kTileBits) | (x & (kTileSize - 1)));
  }

  GridGeometry geometry_;
  int bins_ = 36;
  std::size_t tiles_x_ = 0;
  std::vector<std::unique_ptr<std::int32_t[]>> tiles_;  // only tiles holding candidates
  std::vector<std::uint64_t> candidate_bits_;           // a bit per cell, tile by tile
  std::vector<std::uint32_t> cells_;
  std::vector<std::uint16_t> counts_;  // per candidate: hits[bins], misses[bins]
};

}  // namespace glassmap::grid
