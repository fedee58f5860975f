#pragma once
/// Private: one binary graph-cut move (each variable cell keeps one of two labels), solved with
/// Boost.Graph's boykov_kolmogorov_max_flow on a compressed_sparse_row_graph over the move's cells.

#include <boost/graph/compressed_sparse_row_graph.hpp>
#include <cstdint>
#include <utility>
#include <vector>

#include "glassmap/mrf/energy.hpp"

namespace glassmap::mrf::detail {

/// 8-neighbourhood offsets; direction d and 7 - d are opposite.
inline constexpr int kDx[8] = {-1, 0, 1, -1, 1, -1, 0, 1};
inline constexpr int kDy[8] = {-1, -1, -1, 0, 0, 1, 1, 1};
/// Direction class (edgeClass) of neighbour d.
inline constexpr int kClass[8] = {3, 2, 1, 0, 0, 1, 2, 3};

/// Cells a solver may change: active and with more than one candidate label.
std::vector<uint32_t> movableCells(const LabelEnergy& e);

/// Outcome of one move.
struct MoveOutcome {
  int64_t delta = 0;      ///< exact energy change applied to the labels (<= 0)
  int64_t truncated = 0;  ///< pairwise terms raised to make the move submodular
  bool changed = false;   ///< labels were changed (delta < 0)
};

/// Reusable buffers for binary moves on one energy; sized once per solve.
class BinaryMoveSolver {
 public:
  using Graph = boost::compressed_sparse_row_graph<boost::directedS, boost::no_property, boost::no_property,
                                                   boost::no_property, uint32_t, uint32_t>;
  using Edge = boost::graph_traits<Graph>::edge_descriptor;

  explicit BinaryMoveSolver(const LabelEnergy& e);

  /// Variables of the next move: cell, its label for x = 0 and for x = 1. Every other cell keeps
  /// its label. The current labelling must be one of the two labels of every variable.
  void clear();
  void add(uint32_t cell, uint16_t label0, uint16_t label1);
  /// The same with the cell's unary costs of the two labels given (e.u(cell, label0/1)) by a
  /// caller that keeps them at hand: the unary table is the move's largest random read.
  void add(uint32_t cell, uint16_t label0, uint16_t label1, int32_t unary0, int32_t unary1);
  std::size_t size() const { return vars_.size(); }

  /// Minimises the move energy by max-flow and applies the best move if it lowers E.
  /// A pair term with B + C < A + D (not submodular) is raised on the configurations the current
  /// labelling does not use, so the surrogate E' >= E everywhere and E'(current) = E(current):
  /// the applied move never raises E, but it is then not necessarily the best move.
  /// The change is computed twice: from the cut (constant + max flow - current move energy) and
  /// directly from the labels of the changed cells; when nothing was truncated they must agree
  /// (else std::logic_error). changedCells() lists what moved.
  MoveOutcome run(std::vector<uint16_t>& labels);

  /// Cells whose label the last run() changed.
  const std::vector<uint32_t>& changedCells() const { return changed_; }

 private:
  int64_t changeEnergy(const std::vector<uint16_t>& labels) const;

  const LabelEnergy& e_;
  std::vector<int32_t> node_of_;  // cell -> variable, -1 if none
  std::vector<uint32_t> vars_;
  std::vector<uint16_t> l0_, l1_;
  std::vector<int32_t> u0_, u1_;  // unary cost of l0_ / l1_
  std::vector<uint8_t> cur_, next_;
  std::vector<uint8_t> keep_;  // variable -> stays in the move (not fixed by dominance)
  std::vector<int64_t> th0_, th1_;
  std::vector<int32_t> arc_dir_;  // variable * 8 + direction -> arc index, -1 if none
  std::vector<uint8_t> adir_;     // arc -> its direction (arcs between variables)
  std::vector<uint32_t> tarc_;
  std::vector<uint32_t> changed_;  // variable -> index of its arc to the source (sink follows)
  // The move graph's buffers, kept between moves (their capacity is reused: no allocation and
  // no fresh pages per move).
  Graph graph_;
  std::vector<int64_t> cap_, res_;
  std::vector<Edge> rev_, pred_;
  std::vector<boost::default_color_type> color_;
  std::vector<long> dist_;
};

}  // namespace glassmap::mrf::detail
