#include "glassmap/grid/traversal.hpp"

namespace glassmap::grid {

bool clipToGrid(const GridGeometry& g, const Vec2& a, const Vec2& b, double& t0, double& t1) {
  // Liang-Barsky against [origin, maxCorner]. A hair inside, so floor() of a clipped point on
  // the upper border still names a cell of the grid.
  const Vec2 lo = g.origin, hi = g.maxCorner();
  t0 = 0.0;
  t1 = 1.0;
  // Both ends in the box (most beams): the whole segment, as the divisions below would find it.
  if (a.x() >= lo.x() && a.x() <= hi.x() && a.y() >= lo.y() && a.y() <= hi.y() && b.x() >= lo.x() && b.x() <= hi.x() &&
      b.y() >= lo.y() && b.y() <= hi.y())
    return true;
  const Vec2 d = b - a;
  const double p[4] = {-d.x(), d.x(), -d.y(), d.y()};
  const double q[4] = {a.x() - lo.x(), hi.x() - a.x(), a.y() - lo.y(), hi.y() - a.y()};
  for (int i = 0; i < 4; ++i) {
    if (p[i] == 0.0) {
      if (q[i] < 0.0) return false;
      continue;
    }
    const double r = q[i] / p[i];
    if (p[i] < 0.0) {
      if (r > t1) return false;
      t0 = std::max(t0, r);
    } else {
      if (r < t0) return false;
      t1 = std::min(t1, r);
    }
  }
  return t0 <= t1;
}

std::vector<CellIndex> touchedCells(const GridGeometry& g, const Vec2& a, const Vec2& b) {
  std::vector<CellIndex> cells;
  traverse(g, a, b, [&](int x, int y, double, bool) { cells.push_back({x, y}); });
  return cells;
}

}  // namespace glassmap::grid
