#include "glassmap/vector/label_grid.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "glassmap/core/angles.hpp"
#include "glassmap/core/error.hpp"

namespace glassmap::vector {

double LabelGrid::normalOf(std::uint8_t glass_code) const {
  return wrapHalfTurn(deg2rad((glass_code - kCodeFirstGlass) * angle_bin_deg));
}

void LabelGrid::validate() const {
  if (width < 0 || height < 0) throw Error("label grid has a negative size");
  if (!(resolution > 0)) throw Error("label grid resolution must be positive", {}, 0, "resolution");
  if (!(angle_bin_deg > 0) || angle_bin_deg > 180)
    throw Error("angle bin must be in (0, 180] degrees", {}, 0, "angle_bin_deg");
  if (codes.size() != cells())
    throw Error("label grid has " + std::to_string(codes.size()) + " codes for " + std::to_string(width) + " x " +
                std::to_string(height) + " cells");
  if (!evidence.empty() && evidence.size() != cells())
    throw Error("label grid evidence has " + std::to_string(evidence.size()) + " values for " +
                std::to_string(cells()) + " cells");
  const int bins = static_cast<int>(std::lround(180.0 / angle_bin_deg));
  for (const std::uint8_t c : codes)
    if (isGlassCode(c) && c - kCodeFirstGlass >= bins)
      throw Error("glass code " + std::to_string(c) + " is past the last of " + std::to_string(bins) + " angle bins");
}

LabelGrid makeLabelGrid(int width, int height, double resolution, const Vec2& origin) {
  LabelGrid g;
  g.width = width;
  g.height = height;
  g.resolution = resolution;
  g.origin = origin;
  g.codes.assign(g.cells(), kCodeUnknown);
  return g;
}

std::uint8_t glassCodeOf(double normal, double bin_deg) {
  const int bins = static_cast<int>(std::lround(180.0 / bin_deg));
  const int k = static_cast<int>(std::lround(rad2deg(wrapHalfTurn(normal)) / bin_deg)) % bins;
  return static_cast<std::uint8_t>(kCodeFirstGlass + k);
}

void rasterize(LabelGrid& grid, const VectorMap& map, double min_thickness) {
  const double res = grid.resolution;
  for (const MapSegment& s : map.segments) {
    const double half = 0.5 * std::max(s.thickness, min_thickness);
    const double reach = half + 0.5 * res;
    const Vec2 lo = s.a.cwiseMin(s.b) - Vec2::Constant(reach), hi = s.a.cwiseMax(s.b) + Vec2::Constant(reach);
    const int x0 = std::max(0, static_cast<int>(std::floor((lo.x() - grid.origin.x()) / res)));
    const int y0 = std::max(0, static_cast<int>(std::floor((lo.y() - grid.origin.y()) / res)));
    const int x1 = std::min(grid.width - 1, static_cast<int>(std::floor((hi.x() - grid.origin.x()) / res)));
    const int y1 = std::min(grid.height - 1, static_cast<int>(std::floor((hi.y() - grid.origin.y()) / res)));
    const Vec2 ab = s.b - s.a;
    const double len2 = ab.squaredNorm();
    const Vec2 dir = len2 > 0 ? Vec2(ab / std::sqrt(len2)) : Vec2::UnitX();
    const std::uint8_t code = s.material == Material::Glass
                                  ? glassCodeOf(std::atan2(dir.y(), dir.x()) + 0.5 * kPi, grid.angle_bin_deg)
                                  : kCodeOccupied;
    // A cell belongs to the segment when its centre is within `half` of it, or the segment
    // passes through the cell (so thin panes stay connected).
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const Vec2 c = grid.center(x, y);
        const Vec2 foot = s.closestPoint(c);
        const Vec2 off = (c - foot).cwiseAbs();
        if ((c - foot).norm() <= half || (off.x() <= 0.5 * res && off.y() <= 0.5 * res))
          grid.codes[static_cast<std::size_t>(y) * grid.width + x] = code;
      }
  }
}

}  // namespace glassmap::vector
