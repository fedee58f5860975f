#include "glassmap/grid/hit_miss_grid.hpp"

#include <algorithm>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "glassmap/core/error.hpp"

namespace glassmap::grid {

double OccupancyModel::logOdds(const CellCounts& c) const {
  return std::clamp(c.hits * l_hit + c.misses * l_miss, l_min, l_max);
}

double OccupancyModel::probability(const CellCounts& c) const { return 1.0 / (1.0 + std::exp(-logOdds(c))); }

HitMissGrid::HitMissGrid(const GridGeometry& geometry) : geometry_(geometry) {
  tiles_x_ = (static_cast<std::size_t>(geometry.width) + kTileSize - 1) / kTileSize;
  tiles_y_ = (static_cast<std::size_t>(geometry.height) + kTileSize - 1) / kTileSize;
  tiles_.resize(tiles_x_ * tiles_y_);
}

std::unique_ptr<CellCounts[]> HitMissGrid::allocateTile() {
  ++allocated_;
  return std::make_unique<CellCounts[]>(kTileCells);  // value-initialised: zero counts
}

namespace {

void addTile(CellCounts* dst, const CellCounts* src) {
  for (int i = 0; i < HitMissGrid::kTileCells; ++i) {
    dst[i].hits = static_cast<std::uint16_t>(std::min<unsigned>(0xFFFF, unsigned{dst[i].hits} + src[i].hits));
    dst[i].misses = static_cast<std::uint16_t>(std::min<unsigned>(0xFFFF, unsigned{dst[i].misses} + src[i].misses));
  }
}

}  // namespace

void HitMissGrid::merge(const HitMissGrid& other) {
  if (other.tiles_.size() != tiles_.size()) throw Error("merging grids of different geometry");
  for (std::size_t t = 0; t < tiles_.size(); ++t) {
    const auto& src = other.tiles_[t];
    if (!src) continue;
    auto& dst = tiles_[t];
    if (!dst) dst = allocateTile();
    addTile(dst.get(), src.get());
  }
}

void HitMissGrid::merge(HitMissGrid&& other) {
  if (other.tiles_.size() != tiles_.size()) throw Error("merging grids of different geometry");
  // Tiles only the other grid has move over; tiles both have are added, in parallel (each tile
  // on its own: the sums are the same whatever the split).
  for (std::size_t t = 0; t < tiles_.size(); ++t) {
    if (other.tiles_[t] && !tiles_[t]) {
      tiles_[t] = std::move(other.tiles_[t]);
      ++allocated_;
    }
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tiles_.size(), 64),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t t = r.begin(); t != r.end(); ++t)
                        if (other.tiles_[t]) addTile(tiles_[t].get(), other.tiles_[t].get());
                    });
  for (auto& tile : other.tiles_) tile.reset();
  other.allocated_ = 0;
}

std::size_t HitMissGrid::observedCells() const {
  std::size_t n = 0;
  for (const auto& tile : tiles_) {
    if (!tile) continue;
    for (int i = 0; i < kTileCells; ++i) n += (tile[i].hits | tile[i].misses) != 0;
  }
  return n;
}

std::size_t HitMissGrid::bytes() const {
  return tiles_.size() * sizeof(tiles_[0]) + allocated_ * kTileCells * sizeof(CellCounts);
}

}  // namespace glassmap::grid
