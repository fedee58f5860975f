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

namespace {

// One dimension of the squared distance transform: f sampled at n points -> d (lower envelope of
// parabolas).
void edt1d(const std::vector<float>& f, std::vector<float>& d, std::vector<int>& v, std::vector<float>& z, int n) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  int k = 0;
  v[0] = 0;
  z[0] = -kInf;
  z[1] = kInf;
  // Skip leading infinities: parabolas of infinite height never form the envelope.
  int first = 0;
  while (first < n && f[first] == kInf) ++first;
  if (first == n) {
    std::fill(d.begin(), d.begin() + n, kInf);
    return;
  }
  v[0] = first;
  for (int q = first + 1; q < n; ++q) {
    if (f[q] == kInf) continue;
    float s;
    while (true) {
      const int p = v[k];
      s = ((f[q] + static_cast<float>(q) * q) - (f[p] + static_cast<float>(p) * p)) / (2.0f * (q - p));
      if (s <= z[k] && k > 0) {
        --k;
        continue;
      }
      break;
    }
    ++k;
    v[k] = q;
    z[k] = s;
    z[k + 1] = kInf;
  }
  k = 0;
  for (int q = 0; q < n; ++q) {
    while (z[k + 1] < q) ++k;
    const float dq = static_cast<float>(q - v[k]);
    d[q] = dq * dq + f[v[k]];
  }
}

}  // namespace

std::vector<float> distanceTransform(int width, int height, const std::vector<std::uint8_t>& source) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  std::vector<float> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = source[i] ? 0.0f : kInf;
  const int m = std::max(width, height);
  std::vector<float> f(m), d(m), z(m + 1);
  std::vector<int> v(m);
  for (int x = 0; x < width; ++x) {  // columns
    for (int y = 0; y < height; ++y) f[y] = out[static_cast<std::size_t>(y) * width + x];
    edt1d(f, d, v, z, height);
    for (int y = 0; y < height; ++y) out[static_cast<std::size_t>(y) * width + x] = d[y];
  }
  for (int y = 0; y < height; ++y) {  // rows
    float* row = out.data() + static_cast<std::size_t>(y) * width;
    std::copy(row, row + width, f.begin());
    edt1d(f, d, v, z, width);
    for (int x = 0; x < width; ++x) row[x] = std::sqrt(d[x]);
  }
  return out;
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
