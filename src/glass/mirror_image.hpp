#pragma once
/// What both mirror-image tests (phantoms.cpp, sparse_panes.cpp) ask of a reading a pane may have
/// folded: mirrored back across the pane's line, does it land on the surface that returned it?

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "glassmap/core/labels.hpp"
#include "glassmap/glass/evidence.hpp"

namespace glassmap::glass::detail {

/// True when `reading`, `beyond` [m] past a pane's line of unit normal n (signed along n),
/// mirrored back across that line falls on an occupied or glass cell of `label` (over grid g),
/// within what the line's direction error `tolerance` [rad] makes of the mirrored distance:
/// 1 + 2 |beyond| tan(tolerance) cells either side, at most 4.
inline bool mirrorFallsOnSurface(const grid::GridGeometry& g, const std::vector<std::uint8_t>& label,
                                 const Vec2& reading, const Vec2& n, double beyond, double tolerance) {
  const grid::CellIndex c = g.cellAt(reading - 2.0 * beyond * n);
  const int r = std::min(4, 1 + static_cast<int>(2.0 * std::abs(beyond) * std::tan(tolerance) / g.resolution));
  for (int y = c.y - r; y <= c.y + r; ++y)
    for (int x = c.x - r; x <= c.x + r; ++x) {
      if (!g.contains(x, y)) continue;
      const int l = label[g.index(x, y)];
      if (l == kOccupied || isGlass(l)) return true;
    }
  return false;
}

}  // namespace glassmap::glass::detail
