#include "glassmap/grid/grid_geometry.hpp"

#include "glassmap/core/error.hpp"

namespace glassmap::grid {

GridGeometry coveringGeometry(const Vec2& min, const Vec2& max, double resolution, double margin) {
  if (!(resolution > 0.0)) throw Error("grid resolution must be positive", {}, 0, "resolution");
  if (!(min.x() <= max.x() && min.y() <= max.y())) throw Error("empty extent for a grid");
  GridGeometry g;
  g.resolution = resolution;
  const Vec2 lo = min - Vec2::Constant(margin), hi = max + Vec2::Constant(margin);
  g.origin = Vec2(std::floor(lo.x() / resolution) * resolution, std::floor(lo.y() / resolution) * resolution);
  const double w = std::ceil((hi.x() - g.origin.x()) / resolution);
  const double h = std::ceil((hi.y() - g.origin.y()) / resolution);
  if (w * h > 4.0e9) throw Error("grid too large: " + std::to_string(w) + " x " + std::to_string(h) + " cells");
  g.width = std::max(1, static_cast<int>(w));
  g.height = std::max(1, static_cast<int>(h));
  return g;
}

}  // namespace glassmap::grid
