#include "glassmap/mrf/refine.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_reduce.h>

#include "glassmap/core/error.hpp"

namespace glassmap::mrf {
namespace {

// A unary no candidate cell can afford: keeps the neutral label off every solved cell.
constexpr int32_t kNeverCost = 1 << 28;

// The table over L labels extended by a neutral label L: 0 next to itself and to glass, as EMP
// next to EMP and OCC.
std::vector<int32_t> withNeutralLabel(const std::vector<int32_t>& table, int L) {
  const int n = L + 1;
  std::vector<int32_t> out(static_cast<std::size_t>(n) * n, 0);
  for (int a = 0; a < L; ++a)
    for (int b = 0; b < L; ++b) out[static_cast<std::size_t>(a) * n + b] = table[static_cast<std::size_t>(a) * L + b];
  for (int b = 0; b < L; ++b) {
    const int32_t v = isGlass(b) ? 0 : table[static_cast<std::size_t>(kEmpty) * L + b];
    out[static_cast<std::size_t>(L) * n + b] = v;
    out[static_cast<std::size_t>(b) * n + L] = v;
  }
  return out;
}

}  // namespace

RefineResult refine(glass::CellEvidence& ev, const RefineOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  RefineResult result;
  const int W = ev.geometry.width, H = ev.geometry.height, L = ev.num_labels;
  if (L != numLabels(ev.bins)) throw Error("evidence has inconsistent label count");
  if (options.tile < 8) throw Error("MRF tile must be at least 8 cells", {}, 0, "tile");
  if (options.unary_weight <= 0) throw Error("unary weight must be positive", {}, 0, "unary_weight");
  if (!ev.neutral_cost.empty() && ev.neutral_cost.size() != ev.cells.size())
    throw Error("evidence has a neutral cost per candidate or none", {}, 0, "neutral_cost");
  LabelEnergy psi_only;
  PsiWeights pane_weights;
  pane_weights.pane_angle_full_deg = options.pane_angle_full_deg;
  setPsi(psi_only, options.psi, ev.bins, pane_weights);
  // Cells no beam ended in (beams only passed through them) and unseen cells may be glass that no
  // beam met near its normal: with unseen_glass_neutral they take an extra fixed label that costs
  // nothing next to glass and acts as EMP next to everything else.
  const bool neutral = options.unseen_glass_neutral;
  const int Lx = neutral ? L + 1 : L;
  if (neutral) {
    psi_only.pairwise = withNeutralLabel(psi_only.pairwise, L);
    if (!psi_only.pairwise_dir.empty()) {
      const std::size_t nn = static_cast<std::size_t>(L) * L;
      std::vector<int32_t> dir;
      for (int cls = 0; cls < 4; ++cls) {
        const std::vector<int32_t> one(psi_only.pairwise_dir.begin() + static_cast<std::ptrdiff_t>(cls * nn),
                                       psi_only.pairwise_dir.begin() + static_cast<std::ptrdiff_t>((cls + 1) * nn));
        const std::vector<int32_t> ext = withNeutralLabel(one, L);
        dir.insert(dir.end(), ext.begin(), ext.end());
      }
      psi_only.pairwise_dir = std::move(dir);
    }
  }
  const std::vector<std::uint8_t> before = ev.label;

  // Candidate cells per tile (cells is sorted by linear index y * W + x).
  const int tiles_x = (W + options.tile - 1) / options.tile;
  const int tiles_y = (H + options.tile - 1) / options.tile;
  std::vector<std::vector<std::uint32_t>> tile_cells(static_cast<std::size_t>(tiles_x) * tiles_y);
  for (std::size_t i = 0; i < ev.cells.size(); ++i) {
    const int x = static_cast<int>(ev.cells[i] % static_cast<std::uint32_t>(W));
    const int y = static_cast<int>(ev.cells[i] / static_cast<std::uint32_t>(W));
    tile_cells[static_cast<std::size_t>(y / options.tile) * tiles_x + x / options.tile].push_back(
        static_cast<std::uint32_t>(i));
  }
  result.active_cells = ev.cells.size();

  const auto fixedLabel = [&](std::uint8_t label) -> std::uint16_t {
    if (neutral && (label == kUnknown || label == kEmpty)) return static_cast<std::uint16_t>(L);
    return label == kUnknown ? static_cast<std::uint16_t>(kEmpty) : label;
  };
  // A tile reads its cells and a one-cell border and writes only its own cells, so tiles two apart
  // in x and in y are independent: the sweep solves the four colours of a 2 x 2 pattern in turn
  // (a Gauss-Seidel order that is the same on any number of threads), each colour's tiles in
  // parallel, each thread with its own solver and buffers.
  struct Worker {
    std::unique_ptr<MrfSolver> solver;
    LabelEnergy e;
    std::vector<std::uint16_t> labels;
  };
  tbb::enumerable_thread_specific<Worker> workers([&] {
    return Worker{makeSolver(options.solver, options.solve), {}, {}};
  });
  std::vector<std::int64_t> gaps;  // of the tiles' Psi, which they share: made once
  {
    LabelEnergy table;  // one cell: the table is what counts
    table.width = table.height = 1;
    table.num_labels = Lx;
    table.unary.assign(static_cast<std::size_t>(Lx), 0);
    table.pairwise = psi_only.pairwise;
    table.pairwise_dir = psi_only.pairwise_dir;
    gaps = candidateGaps(table);
  }
  struct Energies {
    std::int64_t before = 0, after = 0;
    int tiles = 0;
    Energies& operator+=(const Energies& o) {
      before += o.before;
      after += o.after;
      tiles += o.tiles;
      return *this;
    }
  };
  const auto solveTile = [&](int tx, int ty, Worker& w) -> Energies {
    const auto& members = tile_cells[static_cast<std::size_t>(ty) * tiles_x + tx];
    if (members.empty()) return {};
    LabelEnergy& e = w.e;
    std::vector<std::uint16_t>& labels = w.labels;
    // The tile plus a one-cell border of fixed neighbours.
    const int x0 = std::max(0, tx * options.tile - 1), y0 = std::max(0, ty * options.tile - 1);
    const int x1 = std::min(W, (tx + 1) * options.tile + 1), y1 = std::min(H, (ty + 1) * options.tile + 1);
    e.width = x1 - x0;
    e.height = y1 - y0;
    e.num_labels = Lx;
    e.pairwise = psi_only.pairwise;
    e.pairwise_dir = psi_only.pairwise_dir;
    const std::size_t n = e.cells();
    e.unary.assign(n * static_cast<std::size_t>(Lx), 0);
    e.active.assign(n, 0);
    e.candidates.clear();
    labels.resize(n);
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x)
        labels[static_cast<std::size_t>(y - y0) * e.width + (x - x0)] =
            fixedLabel(ev.label[static_cast<std::size_t>(y) * W + x]);
    for (const std::uint32_t i : members) {
      const std::uint32_t cell = ev.cells[i];
      const int x = static_cast<int>(cell % static_cast<std::uint32_t>(W)) - x0;
      const int y = static_cast<int>(cell / static_cast<std::uint32_t>(W)) - y0;
      const std::size_t c = static_cast<std::size_t>(y) * e.width + x;
      const float* cost = ev.costs(i);
      for (int l = 0; l < L; ++l)
        e.unary[c * Lx + l] = static_cast<int32_t>(std::lround(options.unary_weight * cost[l] * kCostScale));
      if (neutral) {  // the fixed cells' label, and the candidates' where the classifier offers it
        const bool offered =
            options.candidates_neutral && !ev.neutral_cost.empty() && std::isfinite(ev.neutral_cost[i]);
        e.unary[c * Lx + L] =
            offered ? static_cast<int32_t>(std::lround(options.unary_weight * ev.neutral_cost[i] * kCostScale))
                    : kNeverCost;
      }
      e.active[c] = 1;
      const std::uint8_t own = ev.label[cell];
      labels[c] = own == kUnknown ? static_cast<std::uint16_t>(kEmpty) : own;
    }
    restrictCandidates(e, gaps);
    const MrfResult r = w.solver->solve(e, labels);
    for (const std::uint32_t i : members) {
      const std::uint32_t cell = ev.cells[i];
      const int x = static_cast<int>(cell % static_cast<std::uint32_t>(W)) - x0;
      const int y = static_cast<int>(cell / static_cast<std::uint32_t>(W)) - y0;
      const std::uint16_t l = labels[static_cast<std::size_t>(y) * e.width + x];
      ev.label[cell] = static_cast<std::uint8_t>(l == L ? kEmpty : l);
    }
    return {r.initial_energy, r.energy, 1};
  };
  for (int sweep = 0; sweep < options.sweeps; ++sweep) {
    Energies sum;
    for (int colour = 0; colour < 4; ++colour) {
      std::vector<std::pair<int, int>> tiles;
      for (int ty = colour / 2; ty < tiles_y; ty += 2)
        for (int tx = colour % 2; tx < tiles_x; tx += 2)
          if (!tile_cells[static_cast<std::size_t>(ty) * tiles_x + tx].empty()) tiles.emplace_back(tx, ty);
      // Integer sums: the same whatever the split.
      const Energies part = tbb::parallel_reduce(
          tbb::blocked_range<std::size_t>(0, tiles.size(), 1), Energies{},
          [&](const tbb::blocked_range<std::size_t>& r, Energies acc) {
            Worker& w = workers.local();
            for (std::size_t k = r.begin(); k != r.end(); ++k) acc += solveTile(tiles[k].first, tiles[k].second, w);
            return acc;
          },
          [](Energies a, const Energies& b) { return a += b; });
      sum += part;
    }
    result.tiles += sum.tiles;
    if (sweep == 0) result.energy_before = sum.before;
    result.energy_after = sum.after;
  }
  for (std::size_t c = 0; c < ev.label.size(); ++c) result.changed += ev.label[c] != before[c];
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

}  // namespace glassmap::mrf
