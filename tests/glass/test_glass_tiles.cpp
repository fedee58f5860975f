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
        EXPECT_TRUE(walked.count(c)) << "tile " << tile << " trial " << trial << " cell " << c.first << "," << c.second;
      skipped_cells += static_cast<int>(grid::touchedCells(g, a, b).size() - cells);
      ++met;
    }
    EXPECT_GT(met, 300) << "tile " << tile;
    EXPECT_GT(skipped_cells, 1000) << "tile " << tile;  // the start is not always the beam's own
  }
}

TEST(GlassTiles, TheMarkedRunsWalkVisitsTheMarkedCellsAsTheFullWalkDoes) {
  grid::GridGeometry g;
  g.resolution = 0.05;
  g.origin = Vec2(0.3, -0.2);
  g.width = 120;
  g.height = 80;
  for (const int tile : {2, 4, 8}) {
    std::mt19937 rng(static_cast<unsigned>(100 + tile));
    std::vector<std::uint8_t> marked(g.cells(), 0);
    MarkedTiles tiles(g, tile);
    std::uniform_int_distribution<int> ux(0, g.width - 1), uy(0, g.height - 1), len(1, 30), dir(0, 2);
    for (int wall = 0; wall < 8; ++wall) {  // walls along x, along y and diagonal
      int x = ux(rng), y = uy(rng);
      const int d = dir(rng);
      for (int k = len(rng); k > 0 && g.contains(x, y); --k) {
        marked[g.index(x, y)] = 1;
        tiles.mark(x, y);
        x += d != 1 ? 1 : 0;
        y += d != 0 ? 1 : 0;
      }
    }
    const auto nearMarked = [&](int x, int y) {
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          if (g.contains(x + dx, y + dy) && marked[g.index(x + dx, y + dy)]) return true;
      return false;
    };
    struct Visit {
      int x, y;
      double t;
      bool last;
    };
    std::uniform_real_distribution<double> px(0.0, 6.6), py(-0.5, 4.1);
    std::size_t compared = 0, full_cells = 0, walked_cells = 0;
    for (int trial = 0; trial < 3000; ++trial) {
      const Vec2 a(px(rng), py(rng)), b(px(rng), py(rng));
      std::vector<Visit> full, walked;
      full_cells += grid::traverse(g, a, b, [&](int x, int y, double t, bool last) {
        if (nearMarked(x, y) || last) full.push_back({x, y, t, last});
      });
      std::set<std::pair<int, int>> seen;
      walked_cells += traverseMarked(g, tiles, a, b, [&](int x, int y, double t, bool last) {
        EXPECT_TRUE(seen.emplace(x, y).second) << "visited twice: tile " << tile << " trial " << trial;
        if (nearMarked(x, y) || last) walked.push_back({x, y, t, last});
      });
      // The end cell is walked only when it lies in a marked run (a candidate's always does).
      if (!full.empty() && full.back().last && !nearMarked(full.back().x, full.back().y)) {
        full.pop_back();
        if (!walked.empty() && walked.back().last) walked.pop_back();
      }
      ASSERT_EQ(walked.size(), full.size()) << "tile " << tile << " trial " << trial;
      for (std::size_t i = 0; i < full.size(); ++i) {
        EXPECT_EQ(walked[i].x, full[i].x);
        EXPECT_EQ(walked[i].y, full[i].y);
        EXPECT_NEAR(walked[i].t, full[i].t, 1e-12) << "tile " << tile << " trial " << trial;
        EXPECT_EQ(walked[i].last, full[i].last);
      }
      compared += full.size();
    }
    EXPECT_GT(compared, 3000U) << "tile " << tile;
    EXPECT_LT(walked_cells, full_cells) << "tile " << tile;  // it skips open space
  }
}

}  // namespace
}  // namespace glassmap::glass::detail
