#include "binary_move.hpp"

#include <algorithm>
#include <bit>
#include <boost/graph/boykov_kolmogorov_max_flow.hpp>
#include <boost/graph/compressed_sparse_row_graph.hpp>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

namespace glassmap::mrf::detail {
using Graph = BinaryMoveSolver::Graph;
using Edge = BinaryMoveSolver::Edge;

std::vector<uint32_t> movableCells(const LabelEnergy& e) {
  std::vector<uint32_t> cells;
  for (std::size_t c = 0; c < e.cells(); ++c) {
    if (!e.isActive(c)) continue;
    if (!e.candidates.empty() && std::popcount(e.candidates[c]) < 2) continue;
    cells.push_back(static_cast<uint32_t>(c));
  }
  return cells;
}

BinaryMoveSolver::BinaryMoveSolver(const LabelEnergy& e) : e_(e), node_of_(e.cells(), -1) {}

void BinaryMoveSolver::clear() {
  vars_.clear();
  l0_.clear();
  l1_.clear();
  u0_.clear();
  u1_.clear();
}

void BinaryMoveSolver::add(uint32_t cell, uint16_t label0, uint16_t label1) {
  add(cell, label0, label1, e_.u(cell, label0), e_.u(cell, label1));
}

void BinaryMoveSolver::add(uint32_t cell, uint16_t label0, uint16_t label1, int32_t unary0, int32_t unary1) {
  vars_.push_back(cell);
  l0_.push_back(label0);
  l1_.push_back(label1);
  u0_.push_back(unary0);
  u1_.push_back(unary1);
}

int64_t BinaryMoveSolver::changeEnergy(const std::vector<uint16_t>& labels) const {
  // E(next) - E(current) from the labels alone: every term that touches a changed variable,
  // pairs of two changed variables once (at the lower index).
  const int w = e_.width, h = e_.height;
  auto label = [&](std::size_t k, bool next) { return (next ? next_[k] : cur_[k]) ? l1_[k] : l0_[k]; };
  int64_t delta = 0;
  for (std::size_t k = 0; k < vars_.size(); ++k) {
    if (next_[k] == cur_[k]) continue;
    const uint32_t c = vars_[k];
    const int old_l = label(k, false), new_l = label(k, true);
    delta += int64_t{e_.u(c, new_l)} - e_.u(c, old_l);
    const int x = static_cast<int>(c % w), y = static_cast<int>(c / w);
    for (int d = 0; d < 8; ++d) {
      const int nx = x + kDx[d], ny = y + kDy[d];
      if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
      const std::size_t nc = static_cast<std::size_t>(ny) * w + nx;
      const int32_t j = node_of_[nc];
      if (j < 0) {
        delta += int64_t{e_.psi(new_l, labels[nc], kClass[d])} - e_.psi(old_l, labels[nc], kClass[d]);
      } else if (next_[j] == cur_[j]) {
        const int lj = label(j, false);
        delta += int64_t{e_.psi(new_l, lj, kClass[d])} - e_.psi(old_l, lj, kClass[d]);
      } else if (static_cast<std::size_t>(j) > k) {
        delta += int64_t{e_.psi(new_l, label(j, true), kClass[d])} - e_.psi(old_l, label(j, false), kClass[d]);
      }
    }
  }
  return delta;
}

MoveOutcome BinaryMoveSolver::run(std::vector<uint16_t>& labels) {
  MoveOutcome out;
  changed_.clear();
  if (vars_.empty()) return out;
  const int w = e_.width, h = e_.height;
  for (uint32_t k = 0; k < vars_.size(); ++k) node_of_[vars_[k]] = static_cast<int32_t>(k);
  cur_.assign(vars_.size(), 0);
  for (uint32_t k = 0; k < vars_.size(); ++k) {
    const uint16_t l = labels[vars_[k]];
    if (l != l0_[k] && l != l1_[k]) throw std::logic_error("move variable not at one of its labels");
    cur_[k] = (l == l0_[k]) ? 0 : 1;
  }
  std::ptrdiff_t offset[8];
  for (int d = 0; d < 8; ++d) offset[d] = static_cast<std::ptrdiff_t>(kDy[d]) * w + kDx[d];
  const auto neighbours = [&](uint32_t k, auto&& visit) {  // visit(d, nc) for each neighbour in the grid
    const uint32_t c = vars_[k];
    const int x = static_cast<int>(c % static_cast<uint32_t>(w)), y = static_cast<int>(c / static_cast<uint32_t>(w));
    const bool inside = x > 0 && y > 0 && x < w - 1 && y < h - 1;  // all 8 neighbours exist
    for (int d = 0; d < 8; ++d) {
      if (!inside) {
        const int nx = x + kDx[d], ny = y + kDy[d];
        if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
      }
      visit(d, static_cast<std::size_t>(static_cast<std::ptrdiff_t>(c) + offset[d]));
    }
  };
  // The pair term of variables k and j as the cut minimises it, E'(x_lo, x_hi) = {A, B, C, D} for
  // (0,0), (0,1), (1,0), (1,1) with lo < hi: a term that is not submodular (B + C < A + D) is raised
  // on the configurations the current labelling does not use (Rother et al. 2005), so E' >= E and
  // E'(current) = E(current); `raised` tells whether it was.
  struct Pair {
    int64_t A, B, C, D;
    bool raised;
  };
  const auto pairTerm = [&](uint32_t k, uint32_t j, int cls) {
    const uint32_t lo = std::min(k, j), hi = std::max(k, j);
    Pair p{e_.psi(l0_[lo], l0_[hi], cls), e_.psi(l0_[lo], l1_[hi], cls), e_.psi(l1_[lo], l0_[hi], cls),
           e_.psi(l1_[lo], l1_[hi], cls), false};
    const int64_t deficit = p.A + p.D - p.B - p.C;
    p.raised = deficit > 0;
    if (p.raised) {
      const bool b_used = cur_[lo] == 0 && cur_[hi] == 1, c_used = cur_[lo] == 1 && cur_[hi] == 0;
      if (b_used) {
        p.C += deficit;
      } else if (c_used) {
        p.B += deficit;
      } else {
        p.B += deficit / 2;
        p.C += deficit - deficit / 2;
      }
    }
    return p;
  };
  constexpr std::size_t kGrain = 4096;
  using Range = tbb::blocked_range<uint32_t>;

  // Variables that every minimiser of the move keeps where they are (dominance, a persistency
  // of Boros and Hammer): when E'(x_k = other) - E'(x_k = current) is positive whatever the
  // neighbours take, flipping x_k back from any labelling lowers E'. Such a cell leaves the move
  // and is a fixed neighbour of the others: the minimum and the minimisers are those of the whole
  // move (where a term was raised, the fixed cell's terms with the rest are then exact again: the
  // move is still one that never raises E). In an expansion most cells where alpha is a candidate
  // stay far from taking it. Fixing
  // cells tightens their neighbours' bounds, so the test repeats on the rest while it fixes many.
  // The raised terms are counted in the first round: over the move as posed.
  int64_t raised_terms = -1;
  for (int round = 0; round < 4; ++round) {
    const std::size_t before = vars_.size();
    keep_.resize(vars_.size());
    const int64_t raised_here = tbb::parallel_reduce(
        Range(0, static_cast<uint32_t>(vars_.size()), kGrain), int64_t{0},
        [&](const Range& r, int64_t raised_sum) {
          for (uint32_t k = r.begin(); k != r.end(); ++k) {
            int64_t least = int64_t{u1_[k]} - u0_[k], most = least;  // bounds of E'(x_k = 1) - E'(x_k = 0)
            neighbours(k, [&](int d, std::size_t nc) {
              const int32_t j = node_of_[nc];
              const int cls = kClass[d];
              if (j < 0) {
                const int64_t diff = int64_t{e_.psi(l1_[k], labels[nc], cls)} - e_.psi(l0_[k], labels[nc], cls);
                least += diff;
                most += diff;
                return;
              }
              const auto uj = static_cast<uint32_t>(j);
              const Pair p = pairTerm(k, uj, cls);
              raised_sum += p.raised && k < uj;
              // With x_j = 0 and x_j = 1: from the lower end C - A and D - B, from the upper B - A and D - C.
              const int64_t when0 = k < uj ? p.C - p.A : p.B - p.A, when1 = k < uj ? p.D - p.B : p.D - p.C;
              least += std::min(when0, when1);
              most += std::max(when0, when1);
            });
            keep_[k] = !((cur_[k] == 0 && least > 0) || (cur_[k] == 1 && most < 0));
          }
          return raised_sum;
        },
        std::plus<>());
    {
      uint32_t m = 0;
      for (uint32_t k = 0; k < vars_.size(); ++k) {
        if (!keep_[k]) {
          node_of_[vars_[k]] = -1;
          continue;
        }
        vars_[m] = vars_[k];
        l0_[m] = l0_[k];
        l1_[m] = l1_[k];
        u0_[m] = u0_[k];
        u1_[m] = u1_[k];
        cur_[m] = cur_[k];
        node_of_[vars_[m]] = static_cast<int32_t>(m);
        ++m;
      }
      vars_.resize(m);
      l0_.resize(m);
      l1_.resize(m);
      u0_.resize(m);
      u1_.resize(m);
      cur_.resize(m);
    }
    if (raised_terms < 0) raised_terms = raised_here;
    if (vars_.size() == before || 20 * (before - vars_.size()) < before) break;
  }
  out.truncated = raised_terms;
  const uint32_t n = static_cast<uint32_t>(vars_.size());
  if (n == 0) return out;

  // Arcs sorted by source: per variable its arcs to variable neighbours, then to s and t;
  // then s -> every variable, t -> every variable. Vertices: variables 0..n-1, s = n, t = n + 1.
  // They go straight into the graph's compressed rows (Boost's CSR storage, m_forward, is a
  // public member), refilled in place so its arrays keep their capacity between moves. The
  // variables are handled in parallel blocks (each writes its own arcs and terms; the energy
  // sums are integers, so the graph is the same on any number of threads).
  const uint32_t s = n, t = n + 1;
  Graph& g = graph_;
  std::vector<uint32_t>& row = g.m_forward.m_rowstart;
  std::vector<uint32_t>& col = g.m_forward.m_column;
  row.resize(static_cast<std::size_t>(n) + 3);
  // Every entry a later read uses is written below (a variable's arc towards each neighbour inside
  // the grid): no clearing of the whole array per move.
  arc_dir_.resize(static_cast<std::size_t>(n) * 8);
  tarc_.resize(n);
  th0_.resize(n);
  th1_.resize(n);
  const int L = e_.num_labels;
  const int32_t* table = e_.pairwise_dir.empty() ? e_.pairwise.data() : e_.pairwise_dir.data();
  const std::size_t class_stride = e_.pairwise_dir.empty() ? 0 : static_cast<std::size_t>(L) * L;
  // Arcs per variable (its variable neighbours, s and t), then where each variable's row starts.
  tbb::parallel_for(Range(0, n, kGrain), [&](const Range& r) {
    for (uint32_t k = r.begin(); k != r.end(); ++k) {
      uint32_t count = 2;
      neighbours(k, [&](int, std::size_t nc) { count += node_of_[nc] >= 0 ? 1 : 0; });
      tarc_[k] = count;
    }
  });
  uint32_t pos = 0;
  for (uint32_t k = 0; k < n; ++k) {
    row[k] = pos;
    pos += tarc_[k];
  }
  const uint32_t base_s = pos, base_t = pos + n, arcs = pos + 2 * n;
  row[s] = base_s;
  row[t] = base_t;
  row[t + 1] = arcs;
  col.resize(arcs);
  adir_.resize(arcs);
  // e_cur: the current energy of every term that touches a variable, each once.
  const int64_t e_cur = tbb::parallel_reduce(
      Range(0, n, kGrain), int64_t{0},
      [&](const Range& r, int64_t sum) {
        for (uint32_t k = r.begin(); k != r.end(); ++k) {
          uint32_t at_arc = row[k];
          int64_t t0 = u0_[k], t1 = u1_[k];
          sum += cur_[k] ? u1_[k] : u0_[k];                                    // labels[c] is l0 or l1
          const int32_t* psi0 = table + static_cast<std::size_t>(l0_[k]) * L;  // class 0 rows
          const int32_t* psi1 = table + static_cast<std::size_t>(l1_[k]) * L;
          neighbours(k, [&](int d, std::size_t nc) {
            const int32_t j = node_of_[nc];
            const std::size_t at = kClass[d] * class_stride + labels[nc];
            const int64_t p0 = psi0[at], p1 = psi1[at];
            // A variable neighbour gets an arc (its pair term below); a fixed one's pair term is
            // a unary of this variable. Selects, not branches: which neighbours are variables is data.
            const bool var = j >= 0;
            col[at_arc] = static_cast<uint32_t>(j);
            adir_[at_arc] = static_cast<uint8_t>(d);
            arc_dir_[k * 8 + d] = var ? static_cast<int32_t>(at_arc) : -1;
            at_arc += var ? 1 : 0;
            t0 += var ? 0 : p0;
            t1 += var ? 0 : p1;
            sum += (!var || static_cast<uint32_t>(j) > k) ? (cur_[k] ? p1 : p0) : 0;
          });
          th0_[k] = t0;
          th1_[k] = t1;
          tarc_[k] = at_arc;
          col[at_arc] = s;
          col[at_arc + 1] = t;
          col[base_s + k] = k;
          col[base_t + k] = k;
        }
        return sum;
      },
      std::plus<>());

  std::vector<int64_t>& cap = cap_;
  std::vector<int64_t>& res = res_;
  std::vector<Edge>& rev = rev_;
  // Every capacity is written below; the residuals are Boost's to set (to the capacities).
  cap.resize(arcs);
  res.resize(arcs);
  rev.resize(arcs);
  // Pair terms (Kolmogorov & Zabih 2004): E(x_k, x_j) with A=E(0,0), B=E(0,1), C=E(1,0), D=E(1,1)
  // becomes A + (C-A) x_k + (D-C) x_j + (B+C-A-D) [x_k=0, x_j=1]; x = 0 is the source side. Both
  // ends of a pair compute its terms (the lower one keeps C-A, A and the arc's capacity, the upper
  // one D-C), so no variable writes another's terms.
  struct Sums {
    int64_t constant = 0, truncated = 0;
  };
  const Sums pairs = tbb::parallel_reduce(
      Range(0, n, kGrain), Sums{},
      [&](const Range& r, Sums sums) {
        for (uint32_t k = r.begin(); k != r.end(); ++k) {
          for (uint32_t a = row[k]; a < tarc_[k]; ++a) {  // the arcs to variable neighbours
            const uint32_t j = col[a];
            const int d = adir_[a];
            rev[a] = Edge(j, static_cast<uint32_t>(arc_dir_[j * 8 + (7 - d)]));
            const auto [A, B, C, D, raised] = pairTerm(k, j, kClass[d]);
            if (raised && k < j) ++sums.truncated;
            if (k < j) {
              sums.constant += A;
              th1_[k] += C - A;
              cap[a] = B + C - A - D;
            } else {
              th1_[k] += D - C;
              cap[a] = 0;  // the pair's capacity is on the lower variable's arc; this is its reverse
            }
          }
        }
        return sums;
      },
      [](Sums a, const Sums& b) {
        a.constant += b.constant;
        a.truncated += b.truncated;
        return a;
      });
  const int64_t constant = pairs.constant + tbb::parallel_reduce(
                                                Range(0, n, kGrain), int64_t{0},
                                                [&](const Range& r, int64_t sum) {
                                                  for (uint32_t k = r.begin(); k != r.end(); ++k) {
                                                    const int64_t m = std::min(th0_[k], th1_[k]);
                                                    sum += m;
                                                    cap[base_s + k] = th1_[k] - m;    // s -> k is cut when x_k = 1
                                                    cap[tarc_[k] + 1] = th0_[k] - m;  // k -> t is cut when x_k = 0
                                                    cap[tarc_[k]] = 0;                // k -> s, t -> k: the
                                                    cap[base_t + k] = 0;              // reverses
                                                    rev[base_s + k] = Edge(k, tarc_[k]);
                                                    rev[tarc_[k]] = Edge(s, base_s + k);
                                                    rev[base_t + k] = Edge(k, tarc_[k] + 1);
                                                    rev[tarc_[k] + 1] = Edge(t, base_t + k);
                                                  }
                                                  return sum;
                                                },
                                                std::plus<>());

  std::vector<boost::default_color_type>& color = color_;
  std::vector<Edge>& pred = pred_;
  std::vector<long>& dist = dist_;
  color.resize(n + 2);  // Boost's max-flow starts every vertex gray
  pred.resize(n + 2);
  dist.assign(n + 2, 0);
  const auto eidx = get(boost::edge_index, g);
  const auto vidx = get(boost::vertex_index, g);
  const int64_t flow = boost::boykov_kolmogorov_max_flow(
      g, boost::make_iterator_property_map(cap.begin(), eidx), boost::make_iterator_property_map(res.begin(), eidx),
      boost::make_iterator_property_map(rev.begin(), eidx), boost::make_iterator_property_map(pred.begin(), vidx),
      boost::make_iterator_property_map(color.begin(), vidx), boost::make_iterator_property_map(dist.begin(), vidx),
      vidx, s, t);

  // Source side = the source tree (black) = vertices reachable from s in the residual graph.
  next_.resize(n);
  for (uint32_t k = 0; k < n; ++k)
    next_[k] = color[k] == boost::color_traits<boost::default_color_type>::black() ? 0 : 1;

  const int64_t delta_exact = changeEnergy(labels);
  const int64_t delta_cut = constant + flow - e_cur;
  if (pairs.truncated == 0 && delta_cut != delta_exact)
    throw std::logic_error("graph-cut move energy " + std::to_string(delta_cut) + " differs from direct energy " +
                           std::to_string(delta_exact));
  if (delta_exact < 0) {
    for (uint32_t k = 0; k < n; ++k) {
      if (next_[k] == cur_[k]) continue;
      labels[vars_[k]] = next_[k] ? l1_[k] : l0_[k];
      changed_.push_back(vars_[k]);
    }
    out.delta = pairs.truncated == 0 ? delta_cut : delta_exact;
    out.changed = true;
  }
  for (uint32_t k = 0; k < n; ++k) node_of_[vars_[k]] = -1;
  return out;
}

}  // namespace glassmap::mrf::detail
