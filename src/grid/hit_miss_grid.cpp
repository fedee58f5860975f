#include "glassmap/grid/hit_miss_grid.hpp"

#include <algorithm>
#include <cmath>

namespace glassmap::grid {

double OccupancyModel::logOdds(const CellCounts& c) const {
  return std::clamp(c.hits * l_hit + c.misses * l_miss, l_min, l_max);
}

double OccupancyModel::probability(const CellCounts& c) const {
  return 1.0 / (1.0 + std::exp(-logOdds(c)));
}

HitMissGrid::HitMissGrid(const GridGeometry& geometry) : geometry_(geometry) {
  tiles_x_ = (static_cast<std::size_t>(geometry.width) + kTileSize - 1) / kTileSize;
  tiles_y_ = (static_cast<std::size_t>(geometry.height) + kTileSize - 1) / kTileSize;
  tiles_.resize(tiles_x_ * tiles_y_);
}

std::unique_ptr<CellCounts[]> HitMissGrid::allocateTile() {
  ++allocated_;
  return std::make_unique<CellCounts[]>(kTileCells);  // value-initialised: zero counts
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
