#include "glassmap/grid/angle_histograms.hpp"

#include <algorithm>

#include "glassmap/core/error.hpp"

namespace glassmap::grid {

AngleHistograms::AngleHistograms(const HitMissGrid& counts, int bins, int min_hits)
    : geometry_(counts.geometry()), bins_(bins) {
  if (bins < 1 || bins > 180) throw Error("angle bins must be in 1..180", {}, 0, "bins");
  const GridGeometry& g = geometry_;
  tiles_x_ = (static_cast<std::size_t>(g.width) + kTileSize - 1) / kTileSize;
  const std::size_t tiles_y = (static_cast<std::size_t>(g.height) + kTileSize - 1) / kTileSize;
  tiles_.resize(tiles_x_ * tiles_y);
  static_assert(2 * kTileBits >= 6, "a tile's bits fill whole words");
  candidate_bits_.assign((tiles_.size() << (2 * kTileBits)) / 64, 0);
  const int want = std::max(1, min_hits);
  // Row-major over tiles, then cells, so ids follow tiles (good locality in the hot loop).
  for (std::size_t ty = 0; ty < tiles_y; ++ty) {
    for (std::size_t tx = 0; tx < tiles_x_; ++tx) {
      const int x0 = static_cast<int>(tx) * kTileSize, y0 = static_cast<int>(ty) * kTileSize;
      if (!counts.tileAllocated(x0, y0)) continue;
      for (int dy = 0; dy < kTileSize; ++dy) {
        for (int dx = 0; dx < kTileSize; ++dx) {
          const int x = x0 + dx, y = y0 + dy;
          if (!g.contains(x, y) || counts.get(x, y).hits < want) continue;
          auto& tile = tiles_[ty * tiles_x_ + tx];
          if (!tile) {
            tile = std::make_unique<std::int32_t[]>(kTileSize * kTileSize);
            std::fill_n(tile.get(), kTileSize * kTileSize, kNone);
          }
          tile[(dy << kTileBits) | dx] = static_cast<std::int32_t>(cells_.size());
          const std::size_t bit = ((ty * tiles_x_ + tx) << (2 * kTileBits)) | tileOffset(x, y);
          candidate_bits_[bit >> 6] |= std::uint64_t{1} << (bit & 63);
          cells_.push_back(static_cast<std::uint32_t>(g.index(x, y)));
        }
      }
    }
  }
  counts_.assign(cells_.size() * 2 * static_cast<std::size_t>(bins_), 0);
}

void AngleHistograms::merge(const std::vector<std::uint16_t>& counts) {
  if (counts.size() != counts_.size()) throw Error("merging histograms of a different shape");
  // Bin by bin (countsIndex) into candidate by candidate, a block of candidates at a time (both
  // sides stay in cache).
  const std::size_t n = cells_.size(), row = 2 * static_cast<std::size_t>(bins_);
  constexpr std::size_t kBlock = 512;
  for (std::size_t first = 0; first < n; first += kBlock) {
    const std::size_t last = std::min(n, first + kBlock);
    for (std::size_t k = 0; k < row; ++k) {
      const std::uint16_t* from = &counts[k * n];
      for (std::size_t id = first; id < last; ++id) {
        std::uint16_t& c = counts_[id * row + k];
        c = static_cast<std::uint16_t>(std::min<unsigned>(0xFFFF, unsigned{c} + from[id]));
      }
    }
  }
}

std::size_t AngleHistograms::bytes() const {
  std::size_t tiles = 0;
  for (const auto& t : tiles_) tiles += t ? 1 : 0;
  return tiles_.size() * sizeof(tiles_[0]) + tiles * kTileSize * kTileSize * sizeof(std::int32_t) +
         candidate_bits_.capacity() * sizeof(std::uint64_t) + cells_.capacity() * sizeof(std::uint32_t) +
         counts_.capacity() * sizeof(std::uint16_t);
}

}  // namespace glassmap::grid
