// Step 1 of vectorize(): the cells of one material as a point cloud with a normal and a seed
// score each (glass: its angle label; wall: the minor axis of its neighbourhood).
#include "piece.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "glassmap/core/angles.hpp"

namespace glassmap::vector::detail {

// Cells of one material as a cloud with normals and seed scores.
CellCloud makeCloud(const LabelGrid& grid, Material material, const MaterialOptions& mo) {
  CellCloud cloud;
  cloud.width = grid.width;
  cloud.height = grid.height;
  cloud.resolution = grid.resolution;
  cloud.origin_cells = Vec2::Zero();  // the run's frame: the grid's lower-left corner (see Context)
  cloud.index.assign(grid.cells(), -1);
  for (int y = 0; y < grid.height; ++y)
    for (int x = 0; x < grid.width; ++x) {
      const std::uint8_t code = grid.code(x, y);
      if (material == Material::Glass ? !isGlassCode(code) : !isWallCode(code)) continue;
      const std::size_t li = static_cast<std::size_t>(y) * grid.width + x;
      cloud.index[li] = static_cast<std::int32_t>(cloud.points.size());
      cloud.points.emplace_back((x + 0.5) * grid.resolution, (y + 0.5) * grid.resolution);
      cloud.cell.push_back(static_cast<std::int32_t>(li));
    }
  const std::size_t n = cloud.points.size();
  cloud.normals.resize(n);
  cloud.seed_score.resize(n);
  const auto at = [&](int x, int y) -> std::int32_t {
    if (x < 0 || y < 0 || x >= grid.width || y >= grid.height) return -1;
    return cloud.index[static_cast<std::size_t>(y) * grid.width + x];
  };
  if (material == Material::Glass) {
    const double bin = deg2rad(grid.angle_bin_deg);
    const int bins = static_cast<int>(std::lround(180.0 / grid.angle_bin_deg));
    for (std::size_t i = 0; i < n; ++i) {
      const int li = cloud.cell[i];
      const int x = li % grid.width, y = li / grid.width;
      const int k = grid.code(x, y) - kCodeFirstGlass;
      cloud.normals[i] = Vec2(std::cos(k * bin), std::sin(k * bin));
      // Seeds: cells whose neighbours agree with their angle label.
      int agree = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const std::int32_t j = at(x + dx, y + dy);
          if ((dx == 0 && dy == 0) || j < 0) continue;
          const int kj = grid.code(x + dx, y + dy) - kCodeFirstGlass;
          const int diff = std::abs(k - kj) % bins;
          if (std::min(diff, bins - diff) <= 1) ++agree;
        }
      cloud.seed_score[i] = agree >= 1 ? agree : -1.0;
    }
  } else {
    // Normal of a wall cell: minor axis of the wall cells within normal_radius.
    const int r = std::max(1, static_cast<int>(std::floor(mo.normal_radius / grid.resolution)));
    const double r2 = (mo.normal_radius / grid.resolution) * (mo.normal_radius / grid.resolution);
    for (std::size_t i = 0; i < n; ++i) {
      const int li = cloud.cell[i];
      const int x = li % grid.width, y = li / grid.width;
      Moments m;
      for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx)
          if (dx * dx + dy * dy <= r2 + 1e-9 && at(x + dx, y + dy) >= 0) m.add(Vec2(dx, dy));
      double l_max, l_min, angle;
      m.eigen(l_max, l_min, angle);
      cloud.normals[i] = Vec2(-std::sin(angle), std::cos(angle));
      cloud.seed_score[i] = m.n >= 4 && l_max > 0 ? 1.0 - l_min / l_max : -1.0;
    }
  }
  return cloud;
}

// The floor's dominant wall direction modulo 90 degrees: the direction with the most wall length
}  // namespace glassmap::vector::detail
