#pragma once
/// Exact beam-cell traversal (Amanatides & Woo 1987): every cell whose interior a segment crosses,
/// in order from start to end, without the gaps or extra cells of a Bresenham line.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <type_traits>
#include <vector>

#include "glassmap/grid/grid_geometry.hpp"

namespace glassmap::grid {

/// Clips segment a->b to the grid's box (Liang-Barsky). Returns false if it misses the grid;
/// otherwise sets t0 <= t1 in [0, 1], the parameters of the clipped part.
bool clipToGrid(const GridGeometry& g, const Vec2& a, const Vec2& b, double& t0, double& t1);

/// Visits the cells of segment a->b inside the grid, start cell first, the cell holding b last.
/// visit(int x, int y, double t_enter, bool last): t_enter in [0, 1] is the segment parameter where
/// the segment enters the cell, last is true for the final cell (the one holding b when b lies in
/// the grid). If visit returns bool, false stops the walk.
/// Returns the number of cells visited. A segment exactly through a cell corner steps in x first.
/// With t_from > 0 the walk starts at the cell holding a + t_from (b - a), entered (t_enter) at
/// t_from: the rest of the full walk's cells (up to how a corner exactly on the segment rounds).
template <class Visit>
std::size_t traverse(const GridGeometry& g, const Vec2& a, const Vec2& b, Visit&& visit, double t_from = 0.0) {
  double t0 = 0.0, t1 = 1.0;
  if (!clipToGrid(g, a, b, t0, t1)) return 0;
  if (t_from > t0) {
    if (t_from > t1) return 0;
    t0 = t_from;
  }
  const double inv_res = 1.0 / g.resolution;
  // Grid coordinates (cell units) of the clipped start and end.
  const double ax = (a.x() - g.origin.x()) * inv_res, ay = (a.y() - g.origin.y()) * inv_res;
  const double dx = (b.x() - a.x()) * inv_res, dy = (b.y() - a.y()) * inv_res;
  const double sx = ax + t0 * dx, sy = ay + t0 * dy;
  const double ex = ax + t1 * dx, ey = ay + t1 * dy;
  int x = std::clamp(static_cast<int>(std::floor(sx)), 0, g.width - 1);
  int y = std::clamp(static_cast<int>(std::floor(sy)), 0, g.height - 1);
  const int xe = std::clamp(static_cast<int>(std::floor(ex)), 0, g.width - 1);
  const int ye = std::clamp(static_cast<int>(std::floor(ey)), 0, g.height - 1);
  const int step_x = dx > 0 ? 1 : -1, step_y = dy > 0 ? 1 : -1;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // Parameter t (over the whole segment a->b) of the next x / y cell boundary, and per-cell step.
  const double dt_x = dx != 0.0 ? std::abs(1.0 / dx) : kInf;
  const double dt_y = dy != 0.0 ? std::abs(1.0 / dy) : kInf;
  double t_x = dx != 0.0 ? ((dx > 0 ? x + 1.0 : static_cast<double>(x)) - ax) / dx : kInf;
  double t_y = dy != 0.0 ? ((dy > 0 ? y + 1.0 : static_cast<double>(y)) - ay) / dy : kInf;
  // The walk takes exactly |xe-x| + |ye-y| steps, so it always ends in the end cell.
  int n = std::abs(xe - x) + std::abs(ye - y);
  double t_enter = t0;
  std::size_t visited = 0;
  for (;;) {
    ++visited;
    if constexpr (std::is_same_v<std::invoke_result_t<Visit, int, int, double, bool>, bool>) {
      if (!visit(x, y, t_enter, n == 0)) return visited;
    } else {
      visit(x, y, t_enter, n == 0);
    }
    if (n-- == 0) break;
    // Step across the nearer boundary; if the other axis already reached its end, step the one left.
    const bool go_x = (t_x <= t_y && x != xe) || y == ye;
    if (go_x) {
      t_enter = t_x;
      t_x += dt_x;
      x += step_x;
    } else {
      t_enter = t_y;
      t_y += dt_y;
      y += step_y;
    }
  }
  return visited;
}

/// The cell traverse(g, a, b, visit) visits last (the one holding b when b lies in the grid), by
/// the very arithmetic of the walk, without walking; false when the segment misses the grid.
inline bool lastCell(const GridGeometry& g, const Vec2& a, const Vec2& b, CellIndex& cell) {
  double t0 = 0.0, t1 = 1.0;
  if (!clipToGrid(g, a, b, t0, t1)) return false;
  const double inv_res = 1.0 / g.resolution;
  const double ax = (a.x() - g.origin.x()) * inv_res, ay = (a.y() - g.origin.y()) * inv_res;
  const double dx = (b.x() - a.x()) * inv_res, dy = (b.y() - a.y()) * inv_res;
  const double ex = ax + t1 * dx, ey = ay + t1 * dy;
  cell.x = std::clamp(static_cast<int>(std::floor(ex)), 0, g.width - 1);
  cell.y = std::clamp(static_cast<int>(std::floor(ey)), 0, g.height - 1);
  return true;
}

/// The cells of segment a->b in visiting order (convenience for tests and tools).
std::vector<CellIndex> touchedCells(const GridGeometry& g, const Vec2& a, const Vec2& b);

}  // namespace glassmap::grid
