#pragma once
/// Per-cell glass evidence: the label of every cell and, for the candidate cells, the cost of
/// every label. This is what the MRF stage consumes.

#include <algorithm>
#include <cstdint>
#include <vector>

#include "glassmap/core/labels.hpp"
#include "glassmap/grid/grid_geometry.hpp"

namespace glassmap::glass {

/// Labels and label costs of a mapped grid.
///
/// - `label` is dense over the grid (row 0 = bottom, index y * width + x): kEmpty, kOccupied,
///   glassLabel(k), or kUnknown where no beam passed.
/// - Costs exist only for candidate cells (cells some beam ended in; every other observed cell is
///   EMP with certainty, no beam having stopped there). `cells` lists their linear indices in
///   ascending order; `cost[i * num_labels + l]` is the cost of label l at cells[i]: a negative log
///   posterior [nats] (capped at kMaxCost), so exp(-cost) sums to 1 over the labels of a cell.
struct CellEvidence {
  grid::GridGeometry geometry;       ///< resolution, origin, width, height
  int bins = kDefaultBins;           ///< angle bins; num_labels = 2 + bins
  int num_labels = numLabels();      ///< labels per cell (38 by default)
  std::vector<std::uint8_t> label;   ///< [cell] label, dense
  std::vector<std::uint32_t> cells;  ///< candidate cells, ascending linear indices
  std::vector<float> cost;           ///< [i * num_labels + l] for candidate i
  /// [i] cost [nats] of the MRF's neutral label ("not drawn as glass, but may be glass no beam met
  /// near its normal") for a candidate next to the classifier's glass: its EMP cost plus the
  /// evidence its beams hold against glass of those neighbours' orientations. Infinite where not
  /// offered; empty when the classifier offers it nowhere (see mrf::RefineOptions).
  std::vector<float> neutral_cost;

  static constexpr float kMaxCost = 50.0f;  ///< cap of a cost [nats]

  /// Candidate number of linear cell index, or -1 if the cell has no costs.
  std::int64_t candidate(std::uint32_t cell) const {
    const auto it = std::lower_bound(cells.begin(), cells.end(), cell);
    return it != cells.end() && *it == cell ? it - cells.begin() : -1;
  }
  /// Costs of candidate i (num_labels values).
  const float* costs(std::size_t i) const { return &cost[i * static_cast<std::size_t>(num_labels)]; }
  /// Count of cells per label class.
  std::size_t countGlass() const;
  std::size_t countOccupied() const;
  std::size_t countObserved() const;
};

/// Re-labels every candidate by its least-cost label (ties: lowest label).
void labelByMinimumCost(CellEvidence& evidence);

}  // namespace glassmap::glass
