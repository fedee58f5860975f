#pragma once
/// Coarse tiles of a label grid that hold glass, grown by one tile: a beam whose walk over the tiles
/// meets none of them cannot cross a pane, and most beams of a floor never do.

#include <cstdint>
#include <vector>

#include "glassmap/core/labels.hpp"
#include "glassmap/glass/evidence.hpp"
#include "glassmap/grid/traversal.hpp"

namespace glassmap::glass::detail {

class GlassTiles {
 public:
  explicit GlassTiles(const CellEvidence& e) {
    const grid::GridGeometry& g = e.geometry;
    coarse_.resolution = g.resolution * kTile;
    coarse_.origin = g.origin;
    coarse_.width = (g.width + kTile - 1) / kTile;
    coarse_.height = (g.height + kTile - 1) / kTile;
    glass_.assign(coarse_.cells(), 0);
    for (int y = 0; y < g.height; ++y)
      for (int x = 0; x < g.width; ++x) {
        if (!isGlass(e.label[g.index(x, y)])) continue;
        for (int ty = y / kTile - 1; ty <= y / kTile + 1; ++ty)
          for (int tx = x / kTile - 1; tx <= x / kTile + 1; ++tx)
            if (coarse_.contains(tx, ty)) glass_[coarse_.index(tx, ty)] = 1;
      }
  }
  /// True when segment a -> b passes a tile that holds glass (or its neighbour).
  bool near(const Vec2& a, const Vec2& b) const {
    bool found = false;
    grid::traverse(coarse_, a, b, [&](int x, int y, double, bool) {
      found = glass_[coarse_.index(x, y)] != 0;
      return !found;
    });
    return found;
  }

 private:
  static constexpr int kTile = 4;
  grid::GridGeometry coarse_;
  std::vector<std::uint8_t> glass_;
};

}  // namespace glassmap::glass::detail
