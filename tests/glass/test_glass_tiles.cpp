// The coarse tiles that let the passes over the beams skip the part of a beam before the first
// marked cell (glass, undecided candidates): the walk from where they say meets every marked cell
// of the full walk and every cell next to one.
#include <gtest/gtest.h>

#include <cstdlib>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "glass_tiles.hpp"

namespace glassmap::glass::detail {
namespace {

TEST(GlassTiles, AWalkFromTheFirstMarkedTileMeetsEveryMarkedCell) {
  grid::GridGeometry g;
  g.resolution = 0.05;
  g.origin = Vec2(-1.0, -0.5);
  g.width = 90;
  g.height = 70;
  for (const int tile : {2, 8}) {
    std::mt19937 rng(static_cast<unsigned>(tile));
    std::vector<std::uint8_t> marked(g.cells(), 0);
    MarkedTiles tiles(g, tile);
    std::uniform_int_distribution<int> ux(0, g.width - 1), uy(0, g.height - 1), len(1, 12), dir(0, 1);
    for (int pane = 0; pane < 6; ++pane) {  // short runs of cells, as panes leave them
      int x = ux(rng), y = uy(rng);
      const bool along_x = dir(rng) == 1;
      for (int k = len(rng); k > 0 && g.contains(x, y); --k) {
        marked[g.index(x, y)] = 1;
        tiles.mark(x, y);
        (along_x ? x : y) += 1;
      }
    }
    // Cells within one cell of a marked one (what opaque glass reads before a pane).
    const auto nearMarked = [&](int x, int y) {
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          if (g.contains(x + dx, y + dy) && marked[g.index(x + dx, y + dy)]) return true;
      return false;
    };
    std::uniform_real_distribution<double> px(-1.3, 3.8), py(-0.8, 3.3);
    int met = 0, skipped_cells = 0;
    for (int trial = 0; trial < 3000; ++trial) {
      const Vec2 a(px(rng), py(rng)), b(px(rng), py(rng));
      std::vector<std::pair<int, int>> needed;
      grid::traverse(g, a, b, [&](int x, int y, double, bool) {
        if (nearMarked(x, y)) needed.emplace_back(x, y);
      });
      double from = -1.0;
      const bool near = tiles.near(a, b, &from);
      if (needed.empty()) continue;
      ASSERT_TRUE(near) << "tile " << tile << " trial " << trial;
      ASSERT_GE(from, 0.0);
      std::set<std::pair<int, int>> walked;
      const std::size_t cells = grid::traverse(
          g, a, b, [&](int x, int y, double, bool) { walked.emplace(x, y); }, from);
      for (const auto& c : needed)
        EXPECT_TRUE(walked.count(c)) << "tile " << tile << " trial " << trial << " cell " << c.first << ","
                                     << c.second;
      skipped_cells += static_cast<int>(grid::touchedCells(g, a, b).size() - cells);
      ++met;
    }
    EXPECT_GT(met, 300) << "tile " << tile;
    EXPECT_GT(skipped_cells, 1000) << "tile " << tile;  // the start is not always the beam's own
  }
}

}  // namespace
}  // namespace glassmap::glass::detail
