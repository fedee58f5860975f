#include "glassmap/grid/distance_transform.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace glassmap::grid {

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

}  // namespace glassmap::grid
