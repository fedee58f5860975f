#include <algorithm>
#include <bit>
#include <chrono>
#include <cstdlib>
#include <ctime>

#include "binary_move.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/mrf/solver.hpp"

namespace glassmap::mrf {
namespace {

using Clock = std::chrono::steady_clock;

void checkInput(const LabelEnergy& e, const std::vector<uint16_t>& labels) {
  validate(e);
  if (labels.size() != e.cells()) throw Error("one start label per cell expected", {}, 0, "labels");
  for (uint16_t l : labels)
    if (l >= e.num_labels) throw Error("start label out of range", {}, 0, "labels");
}

/// Runs cycles of `cycle` (which returns the energy gained) until the gain is small.
template <typename Cycle>
void runCycles(const MrfOptions& o, MrfResult& r, Cycle&& cycle) {
  while (r.cycles < o.max_cycles) {
    const int64_t before = r.energy;
    cycle();
    ++r.cycles;
    const int64_t gain = before - r.energy;
    if (gain <= 0 || static_cast<double>(gain) < o.min_cycle_gain * std::llabs(before)) {
      r.converged = true;
      break;
    }
  }
}

/// Alpha-beta swap (Boykov, Veksler, Zabih 2001): for every label pair, the cells labelled alpha
/// or beta (and for which the other label is a candidate) choose between the two by one min-cut.
/// Needs Psi(a,b) + Psi(b,a) >= Psi(a,a) + Psi(b,b) (true for Psi >= 0 with zero diagonal):
/// then every move is the exact optimal swap and the result is a swap-local minimum.
class SwapSolver final : public MrfSolver {
 public:
  explicit SwapSolver(MrfOptions o) : o_(o) {}
  std::string name() const override { return "swap"; }

  MrfResult solve(const LabelEnergy& e, std::vector<uint16_t>& labels) override {
    const auto t0 = Clock::now();
    const std::clock_t c0 = std::clock();
    checkInput(e, labels);
    MrfResult r;
    r.initial_energy = r.energy = energy(e, labels);
    const int L = e.num_labels;
    // Movable cells bucketed by current label; a swap only moves cells between its two buckets.
    std::vector<std::vector<uint32_t>> bucket(L);
    for (uint32_t c : detail::movableCells(e)) bucket[labels[c]].push_back(c);
    detail::BinaryMoveSolver move(e);
    std::vector<uint32_t> merged;
    // A swap's move problem depends only on the cells labelled a or b and their neighbours'
    // labels. stamp[l] = last time a cell labelled l, or next to one, changed; a pair whose last
    // run found nothing and whose labels are unstamped since would find nothing again: skip it.
    int64_t now = 1;
    std::vector<int64_t> stamp(L, 1), last_run(static_cast<std::size_t>(L) * L, 0);
    const int w = e.width, h = e.height;
    runCycles(o_, r, [&] {
      for (int a = 0; a < L; ++a) {
        for (int b = a + 1; b < L; ++b) {
          if (bucket[a].empty() && bucket[b].empty()) continue;
          int64_t& last = last_run[a * L + b];
          if (stamp[a] < last && stamp[b] < last) continue;
          move.clear();
          for (uint32_t c : bucket[a])
            if (e.isCandidate(c, b)) move.add(c, static_cast<uint16_t>(a), static_cast<uint16_t>(b));
          for (uint32_t c : bucket[b])
            if (e.isCandidate(c, a)) move.add(c, static_cast<uint16_t>(a), static_cast<uint16_t>(b));
          const detail::MoveOutcome m = move.run(labels);
          r.truncated_terms += m.truncated;
          ++now;
          if (m.changed) {
            r.energy += m.delta;
            ++r.moves;
            for (uint32_t c : move.changedCells()) {
              stamp[a] = stamp[b] = now;
              const int x = static_cast<int>(c % w), y = static_cast<int>(c / w);
              for (int d = 0; d < 8; ++d) {
                const int nx = x + detail::kDx[d], ny = y + detail::kDy[d];
                if (nx >= 0 && ny >= 0 && nx < w && ny < h) stamp[labels[ny * w + nx]] = now;
              }
            }
            merged.clear();
            merged.insert(merged.end(), bucket[a].begin(), bucket[a].end());
            merged.insert(merged.end(), bucket[b].begin(), bucket[b].end());
            bucket[a].clear();
            bucket[b].clear();
            for (uint32_t c : merged) bucket[labels[c]].push_back(c);
          }
          // An exact optimal swap repeated at once finds nothing; a truncated one might.
          last = m.truncated == 0 ? ++now : now;
        }
      }
    });
    r.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    r.cpu_seconds = double(std::clock() - c0) / CLOCKS_PER_SEC;
    return r;
  }

 private:
  MrfOptions o_;
};

/// Alpha-expansion (Boykov, Veksler, Zabih 2001): for every label alpha, the cells where alpha is a
/// candidate either keep their label or take alpha, by one min-cut. Pair terms that are not
/// submodular for a move (with the paper's Psi: expanding EMP or OCC across two glass labels of
/// different angle) are truncated as in Rother et al. 2005: the move never raises E, but it is no
/// longer the optimal expansion, so neither expansion-local optimality nor the factor-2 bound
/// of metric energies holds for those labels. MrfResult::truncated_terms counts them.
class ExpansionSolver final : public MrfSolver {
 public:
  explicit ExpansionSolver(MrfOptions o) : o_(o) {}
  std::string name() const override { return "expansion"; }

  MrfResult solve(const LabelEnergy& e, std::vector<uint16_t>& labels) override {
    const auto t0 = Clock::now();
    const std::clock_t c0 = std::clock();
    checkInput(e, labels);
    MrfResult r;
    r.initial_energy = r.energy = energy(e, labels);
    const int L = e.num_labels;
    // Per label the movable cells where it is a candidate (fixed for the whole solve), with the
    // label's unary there, and per cell the unary of its current label: a move then reads its
    // unaries in order instead of from the whole cells x labels table.
    std::vector<std::vector<uint32_t>> where(L);
    std::vector<std::vector<int32_t>> where_u(L);
    for (uint32_t c : detail::movableCells(e))
      for (int l = 0; l < L; ++l)
        if (e.isCandidate(c, l)) {
          where[l].push_back(c);
          where_u[l].push_back(e.u(c, l));
        }
    std::vector<int32_t> u_now(e.cells());
    for (std::size_t c = 0; c < e.cells(); ++c) u_now[c] = e.u(c, labels[c]);
    detail::BinaryMoveSolver move(e);
    // An alpha move depends on the labels in alpha's candidate region and next to it. When a cell
    // changes, every label that is a candidate at it or at a neighbour gets stamped; an alpha
    // whose last exact move found nothing and that is unstamped since would find nothing again.
    int64_t now = 1;
    std::vector<int64_t> stamp(L, 1), last_run(L, 0);
    const int w = e.width, h = e.height;
    const uint64_t all = L >= 64 ? ~uint64_t{0} : (uint64_t{1} << L) - 1;
    runCycles(o_, r, [&] {
      for (int a = 0; a < L; ++a) {
        if (stamp[a] < last_run[a]) continue;
        move.clear();
        for (std::size_t i = 0; i < where[a].size(); ++i) {
          const uint32_t c = where[a][i];
          if (labels[c] != a) move.add(c, labels[c], static_cast<uint16_t>(a), u_now[c], where_u[a][i]);
        }
        const detail::MoveOutcome m = move.run(labels);
        r.truncated_terms += m.truncated;
        ++now;
        if (m.changed) {
          r.energy += m.delta;
          ++r.moves;
          for (uint32_t c : move.changedCells()) u_now[c] = e.u(c, labels[c]);
          if (L > 64) {
            std::fill(stamp.begin(), stamp.end(), now);
          } else {
            for (uint32_t c : move.changedCells()) {
              const int x = static_cast<int>(c % w), y = static_cast<int>(c / w);
              uint64_t affected = e.candidates.empty() ? all : e.candidates[c];
              for (int d = 0; d < 8 && affected != all; ++d) {
                const int nx = x + detail::kDx[d], ny = y + detail::kDy[d];
                if (nx >= 0 && ny >= 0 && nx < w && ny < h)
                  affected |= e.candidates[static_cast<std::size_t>(ny) * w + nx];
              }
              for (uint64_t bits = affected; bits != 0; bits &= bits - 1) stamp[std::countr_zero(bits)] = now;
            }
          }
        }
        // An optimal expansion repeated at once finds nothing; a truncated one might.
        last_run[a] = m.truncated == 0 ? ++now : now;
      }
    });
    r.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    r.cpu_seconds = double(std::clock() - c0) / CLOCKS_PER_SEC;
    return r;
  }

 private:
  MrfOptions o_;
};

/// Iterated conditional modes (Besag 1986): cells in scan order take their best candidate label
/// given their neighbours, while that strictly lowers E.
class IcmSolver final : public MrfSolver {
 public:
  explicit IcmSolver(MrfOptions o) : o_(o) {}
  std::string name() const override { return "icm"; }

  MrfResult solve(const LabelEnergy& e, std::vector<uint16_t>& labels) override {
    const auto t0 = Clock::now();
    const std::clock_t c0 = std::clock();
    checkInput(e, labels);
    MrfResult r;
    r.initial_energy = r.energy = energy(e, labels);
    const std::vector<uint32_t> cells = detail::movableCells(e);
    const int w = e.width, h = e.height, L = e.num_labels;
    int neighbours[8], classes[8];
    runCycles(o_, r, [&] {
      for (uint32_t c : cells) {
        const int x = static_cast<int>(c % w), y = static_cast<int>(c / w);
        int count = 0;
        for (int d = 0; d < 8; ++d) {
          const int nx = x + detail::kDx[d], ny = y + detail::kDy[d];
          if (nx >= 0 && ny >= 0 && nx < w && ny < h) {
            classes[count] = detail::kClass[d];
            neighbours[count++] = labels[ny * w + nx];
          }
        }
        auto local = [&](int l) {
          int64_t v = e.u(c, l);
          for (int i = 0; i < count; ++i) v += e.psi(l, neighbours[i], classes[i]);
          return v;
        };
        const int old = labels[c];
        int best = old;
        int64_t best_v = local(old);
        for (int l = 0; l < L; ++l) {
          if (l == old || !e.isCandidate(c, l)) continue;
          const int64_t v = local(l);
          if (v < best_v) {
            best_v = v;
            best = l;
          }
        }
        if (best != old) {
          r.energy += best_v - local(old);
          labels[c] = static_cast<uint16_t>(best);
          ++r.moves;
        }
      }
    });
    r.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    r.cpu_seconds = double(std::clock() - c0) / CLOCKS_PER_SEC;
    return r;
  }

 private:
  MrfOptions o_;
};

}  // namespace

const char* toString(SolverKind kind) {
  switch (kind) {
    case SolverKind::Icm: return "icm";
    case SolverKind::Swap: return "swap";
    case SolverKind::Expansion: return "expansion";
  }
  return "?";
}

SolverKind parseSolver(const std::string& name) {
  for (SolverKind k : allSolvers())
    if (name == toString(k)) return k;
  throw Error("unknown MRF solver '" + name + "' (expected swap, expansion or icm)", {}, 0, "solver");
}

std::vector<SolverKind> allSolvers() { return {SolverKind::Icm, SolverKind::Swap, SolverKind::Expansion}; }

std::unique_ptr<MrfSolver> makeSolver(SolverKind kind, const MrfOptions& options) {
  switch (kind) {
    case SolverKind::Icm: return std::make_unique<IcmSolver>(options);
    case SolverKind::Swap: return std::make_unique<SwapSolver>(options);
    case SolverKind::Expansion: return std::make_unique<ExpansionSolver>(options);
  }
  throw Error("unknown MRF solver kind", {}, 0, "solver");
}

}  // namespace glassmap::mrf
