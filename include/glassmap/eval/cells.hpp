#pragma once
/// Cell-level evaluation of a glass map against the true floorplan (paper section 2.5.6, Table I).

#include <cstdint>
#include <vector>

#include "glassmap/geometry/vector_map.hpp"
#include "glassmap/grid/grid_geometry.hpp"

namespace glassmap::eval {

/// Options of the cell evaluation.
struct CellEvalOptions {
  int tolerance_cells = 2;  ///< displacement allowed for "found with displacement" [cells, Chebyshev]
};

/// Standard detection scores.
struct DetectionScores {
  double precision = 0.0;  ///< correct predicted glass cells / predicted glass cells
  double recall = 0.0;     ///< detected true glass cells / true glass cells
  double f1 = 0.0;         ///< harmonic mean of precision and recall
};

/// Table I columns and standard scores.
///
/// Paper columns: ground_truth = true glass cells (glass segments rasterised at the map's cells);
/// found = predicted glass cells within tolerance of a true cell; false_positives = the other
/// predicted glass cells (found + false_positives = predicted); exact_found = true cells predicted
/// glass in the same cell; found_displaced = true cells not exactly found but with a predicted glass
/// cell within tolerance; not_found = the rest.
struct CellEvalResult {
  int tolerance_cells = 2;
  std::size_t ground_truth = 0;
  std::size_t predicted = 0;
  std::size_t found = 0;
  std::size_t false_positives = 0;
  std::size_t exact_found = 0;
  std::size_t found_displaced = 0;
  std::size_t not_found = 0;
  std::size_t truth_outside = 0;      ///< true glass cells outside the map's extent (counted as not found)
  DetectionScores exact;              ///< at 0 cells tolerance
  DetectionScores tolerant;           ///< at tolerance_cells
  double paper_recall = 0.0;          ///< the paper's "recall": found / ground truth
  double paper_precision = 0.0;       ///< the paper's "precision": exact_found / ground truth
  double mean_angle_error_deg = 0.0;  ///< mean |pane angle error| of found cells vs nearest true cell [deg]
  std::size_t angle_cells = 0;        ///< cells in that mean
};

/// True glass cells: per cell of g the pane-normal direction in [0, pi) [rad], NaN where no glass.
/// Each glass segment marks every cell it crosses (exact traversal); cells outside g are counted
/// in *outside if given.
std::vector<float> rasteriseGlass(const VectorMap& truth, const grid::GridGeometry& g, std::size_t* outside = nullptr);

/// Scores a label grid (glass labels: 2 + k with pane normal at k * 180 / bins deg; see core/labels.hpp).
CellEvalResult evaluateCells(const VectorMap& truth, const grid::GridGeometry& g,
                             const std::vector<std::uint8_t>& labels, int bins = 36,
                             const CellEvalOptions& options = {});

}  // namespace glassmap::eval
