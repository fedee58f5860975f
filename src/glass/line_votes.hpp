#pragma once
/// Line votes of the sparse-pane search (glass/sparse_panes.hpp): every weak return votes for the
/// line normal to its beam through it; seed lines are the local maxima of the votes.

#include <cmath>
#include <vector>

#include "glassmap/grid/grid_geometry.hpp"
#include "weak_returns.hpp"

namespace glassmap::glass::sparse {

/// The line n . p = rho, n = (cos angle, sin angle), angle in [0, pi).
struct Line {
  double angle = 0.0;
  double rho = 0.0;
  Vec2 normal() const { return {std::cos(angle), std::sin(angle)}; }
  Vec2 tangent() const { return {-std::sin(angle), std::cos(angle)}; }
};

/// Seed lines: local maxima of the votes summed over +-pad angle bins and +-wr offset bins, with at
/// least min_votes, strongest first. Offsets are voted relative to the grid's centre.
std::vector<Line> seedLines(const std::vector<WeakReturn>& weak, const grid::GridGeometry& g, int pad, int wr,
                            int min_votes);

}  // namespace glassmap::glass::sparse
