#include "grid_util.hpp"

#include <algorithm>
#include <limits>

namespace glassmap::vector::detail {

Components connectedComponents(int width, int height, const std::vector<std::uint8_t>& in, bool eight) {
  Components c;
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  c.label.assign(n, -1);
  std::vector<std::size_t> stack;
  for (std::size_t start = 0; start < n; ++start) {
    if (!in[start] || c.label[start] >= 0) continue;
    const auto k = static_cast<std::int32_t>(c.sizes.size());
    c.sizes.push_back(0);
    c.label[start] = k;
    stack.push_back(start);
    while (!stack.empty()) {
      const std::size_t i = stack.back();
      stack.pop_back();
      ++c.sizes.back();
      const int x = static_cast<int>(i % static_cast<std::size_t>(width));
      const int y = static_cast<int>(i / static_cast<std::size_t>(width));
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          if ((dx == 0 && dy == 0) || (!eight && dx != 0 && dy != 0)) continue;
          const int nx = x + dx, ny = y + dy;
          if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
          const std::size_t j = static_cast<std::size_t>(ny) * static_cast<std::size_t>(width) + nx;
          if (!in[j] || c.label[j] >= 0) continue;
          c.label[j] = k;
          stack.push_back(j);
        }
    }
  }
  return c;
}

void walkCells(const Vec2& p, const Vec2& q, int width, int height, const std::function<bool(int, int)>& visit) {
  int x = static_cast<int>(std::floor(p.x())), y = static_cast<int>(std::floor(p.y()));
  const int xe = static_cast<int>(std::floor(q.x())), ye = static_cast<int>(std::floor(q.y()));
  const Vec2 d = q - p;
  const int sx = d.x() > 0 ? 1 : -1, sy = d.y() > 0 ? 1 : -1;
  constexpr double kBig = std::numeric_limits<double>::infinity();
  const double dtx = d.x() != 0 ? std::abs(1.0 / d.x()) : kBig, dty = d.y() != 0 ? std::abs(1.0 / d.y()) : kBig;
  double tx = d.x() != 0 ? ((sx > 0 ? (x + 1 - p.x()) : (p.x() - x)) * dtx) : kBig;
  double ty = d.y() != 0 ? ((sy > 0 ? (y + 1 - p.y()) : (p.y() - y)) * dty) : kBig;
  const int steps = std::abs(xe - x) + std::abs(ye - y);
  for (int k = 0; k <= steps; ++k) {
    if (x < 0 || y < 0 || x >= width || y >= height) return;
    if (!visit(x, y)) return;
    if (tx < ty) {
      tx += dtx;
      x += sx;
    } else {
      ty += dty;
      y += sy;
    }
  }
}

}  // namespace glassmap::vector::detail
