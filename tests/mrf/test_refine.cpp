#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include <tbb/global_control.h>

#include "glassmap/core/error.hpp"
#include "glassmap/mrf/energy.hpp"

#include "glassmap/mrf/refine.hpp"

using namespace glassmap;

namespace {

// Costs (negative log posteriors [nats]): `best` 0.2, `second` 1.2, the rest `others`.
void setCosts(glass::CellEvidence& ev, std::size_t i, int best, int second, float others) {
  float* c = &ev.cost[i * static_cast<std::size_t>(ev.num_labels)];
  for (int l = 0; l < ev.num_labels; ++l) c[l] = (l == best) ? 0.2f : (l == second ? 1.2f : others);
}

// A 48 x 48 grid, all empty; a horizontal pane (GLS bin 0) along y = 24, x = 6..41, confident
// (5 nats against EMP: a pane cell pays 6 x 0.6 for its empty neighbours), where every 5th pane
// cell's evidence points at a wrong angle with bin 0 second; plus isolated weak glass cells in
// free space whose second-best label is EMP.
glass::CellEvidence noisyPane(unsigned seed) {
  glass::CellEvidence ev;
  ev.geometry.width = 48;
  ev.geometry.height = 48;
  ev.label.assign(48 * 48, kEmpty);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> wrong(3, 33);
  std::vector<std::pair<std::uint32_t, int>> cands;
  for (int x = 6; x <= 41; ++x) cands.emplace_back(24 * 48 + x, x % 5 == 0 ? glassLabel(wrong(rng)) : glassLabel(0));
  for (int k = 0; k < 12; ++k) {
    const int x = 3 + static_cast<int>(rng() % 42), y = 3 + static_cast<int>(rng() % 15);
    cands.emplace_back(static_cast<std::uint32_t>(y * 48 + x), glassLabel(wrong(rng)));
  }
  std::sort(cands.begin(), cands.end());
  for (const auto& [cell, best] : cands) {
    ev.cells.push_back(cell);
    ev.cost.resize(ev.cells.size() * ev.num_labels);
    const bool isolated = cell / 48 != 24;
    setCosts(ev, ev.cells.size() - 1, best, isolated ? kEmpty : glassLabel(0), isolated ? 1.5f : 5.0f);
    ev.label[cell] = static_cast<std::uint8_t>(best);
  }
  return ev;
}

// Energy of the whole labelling as refine() minimises it tile by tile: weighted costs of the
// candidate cells plus Psi over every 8-neighbour pair of the grid (unknown counts as empty).
std::int64_t globalEnergy(const glass::CellEvidence& ev, const mrf::RefineOptions& o) {
  mrf::LabelEnergy e;
  e.width = ev.geometry.width;
  e.height = ev.geometry.height;
  e.num_labels = ev.num_labels;
  mrf::setPsi(e, o.psi, ev.bins);
  e.unary.assign(e.cells() * static_cast<std::size_t>(e.num_labels), 0);
  for (std::size_t i = 0; i < ev.cells.size(); ++i)
    for (int l = 0; l < e.num_labels; ++l)
      e.unary[ev.cells[i] * static_cast<std::size_t>(e.num_labels) + l] =
          static_cast<std::int32_t>(std::lround(o.unary_weight * ev.costs(i)[l] * mrf::kCostScale));
  std::vector<std::uint16_t> labels(ev.label.begin(), ev.label.end());
  for (auto& l : labels)
    if (l == kUnknown) l = kEmpty;
  return mrf::energy(e, labels);
}

}  // namespace

TEST(MrfRefine, CleansANoisyPaneAndDropsIsolatedGlass) {
  for (const mrf::SolverKind solver : {mrf::SolverKind::Swap, mrf::SolverKind::Expansion}) {
    for (unsigned seed = 1; seed <= 3; ++seed) {
      glass::CellEvidence ev = noisyPane(seed);
      mrf::RefineOptions o;
      o.solver = solver;
      o.psi = mrf::PsiKind::Closed;  // the costs below; the pane Psi charges an isolated cell only its two ends
      // The isolated cells here sit among cells no beam ended in: the paper's grid charges them
      // their empty neighbours (the default leaves those neutral: a sparse pane looks the same).
      o.unseen_glass_neutral = false;
      o.tile = 20;                   // several tiles: the pane crosses tile borders
      // Unaries weighted 3x against Psi: at weight 1 a pane cell next to a wrong-angle cell pays
      // 3 + 6 x 0.6 as glass but only 5 + 2 x 0.6 as EMP, and local moves punch holes in the pane.
      o.unary_weight = 3.0;
      const std::int64_t before = globalEnergy(ev, o);
      const mrf::RefineResult r = mrf::refine(ev, o);
      EXPECT_GT(r.changed, 0u);
      EXPECT_LT(globalEnergy(ev, o), before) << mrf::toString(solver) << " seed " << seed;
      for (int x = 6; x <= 41; ++x)
        EXPECT_EQ(ev.label[24 * 48 + x], glassLabel(0)) << mrf::toString(solver) << " x=" << x;
      for (int y = 0; y < 20; ++y)
        for (int x = 0; x < 48; ++x) EXPECT_FALSE(isGlass(ev.label[y * 48 + x])) << mrf::toString(solver);
    }
  }
}

TEST(MrfRefine, DeterministicAndTileSizeIndependentOnThisCase) {
  glass::CellEvidence a = noisyPane(9), b = noisyPane(9), c = noisyPane(9);
  mrf::RefineOptions o;
  o.unary_weight = 3.0;
  mrf::refine(a, o);
  mrf::refine(b, o);
  o.tile = 16;
  mrf::refine(c, o);
  EXPECT_EQ(a.label, b.label);
  EXPECT_EQ(a.label, c.label);
}

TEST(MrfRefine, TheSameLabelsOnOneThreadAsOnMany) {
  // Tiles of one colour of a 2 x 2 pattern are solved in parallel: small tiles, many of them.
  for (const int tile : {8, 12}) {
    glass::CellEvidence serial = noisyPane(4), parallel = noisyPane(4);
    mrf::RefineOptions o;
    o.unary_weight = 3.0;
    o.tile = tile;
    mrf::RefineResult rs, rp;
    {
      tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
      rs = mrf::refine(serial, o);
    }
    {
      tbb::global_control four(tbb::global_control::max_allowed_parallelism, 4);
      rp = mrf::refine(parallel, o);
    }
    EXPECT_EQ(serial.label, parallel.label) << "tile " << tile;
    EXPECT_EQ(rs.energy_before, rp.energy_before);
    EXPECT_EQ(rs.energy_after, rp.energy_after);
    EXPECT_EQ(rs.tiles, rp.tiles);
    EXPECT_GT(rs.tiles, 8);
  }
}

TEST(MrfRefine, RejectsBadOptions) {
  glass::CellEvidence ev = noisyPane(1);
  mrf::RefineOptions o;
  o.tile = 2;
  EXPECT_THROW(mrf::refine(ev, o), Error);
}
