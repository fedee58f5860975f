#pragma once
/// Nelder-Mead simplex minimisation of a small smooth function (the calibration's 2- and
/// 3-parameter likelihood fits). Eigen has no derivative-free minimiser outside its unsupported
/// modules, and these fits are too small to justify another dependency.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

namespace glassmap::sensor {

template <std::size_t N>
struct SimplexResult {
  std::array<double, N> x{};
  double value = 0.0;
};

/// Minimises f from x0 with initial steps `step`; stops after max_evals evaluations or when the
/// simplex's values agree within 1e-10 (relative).
template <std::size_t N, class F>
SimplexResult<N> nelderMead(F&& f, const std::array<double, N>& x0, const std::array<double, N>& step, int max_evals) {
  using Point = std::array<double, N>;
  std::array<Point, N + 1> pts;
  std::array<double, N + 1> val;
  pts[0] = x0;
  for (std::size_t i = 0; i < N; ++i) {
    pts[i + 1] = x0;
    pts[i + 1][i] += step[i];
  }
  int evals = 0;
  for (std::size_t i = 0; i <= N; ++i) val[i] = f(pts[i]), ++evals;
  auto blend = [](const Point& a, const Point& b, double t) {  // a + t (b - a)
    Point r;
    for (std::size_t i = 0; i < N; ++i) r[i] = a[i] + t * (b[i] - a[i]);
    return r;
  };
  while (evals < max_evals) {
    std::array<std::size_t, N + 1> order;
    for (std::size_t i = 0; i <= N; ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return val[a] < val[b]; });
    const std::size_t best = order[0], worst = order[N], second = order[N - 1];
    if (std::abs(val[worst] - val[best]) <= 1e-10 * (std::abs(val[best]) + 1e-10)) break;
    Point centroid{};
    for (std::size_t i = 0; i <= N; ++i)
      if (i != worst)
        for (std::size_t j = 0; j < N; ++j) centroid[j] += pts[i][j] / static_cast<double>(N);
    const Point reflected = blend(centroid, pts[worst], -1.0);
    const double fr = f(reflected);
    ++evals;
    if (fr < val[best]) {
      const Point expanded = blend(centroid, pts[worst], -2.0);
      const double fe = f(expanded);
      ++evals;
      if (fe < fr)
        pts[worst] = expanded, val[worst] = fe;
      else
        pts[worst] = reflected, val[worst] = fr;
    } else if (fr < val[second]) {
      pts[worst] = reflected, val[worst] = fr;
    } else {
      const Point contracted = blend(centroid, fr < val[worst] ? reflected : pts[worst], 0.5);
      const double fc = f(contracted);
      ++evals;
      if (fc < std::min(fr, val[worst])) {
        pts[worst] = contracted, val[worst] = fc;
      } else {
        for (std::size_t i = 0; i <= N; ++i) {
          if (i == best) continue;
          pts[i] = blend(pts[best], pts[i], 0.5);
          val[i] = f(pts[i]);
          ++evals;
        }
      }
    }
  }
  std::size_t best = 0;
  for (std::size_t i = 1; i <= N; ++i)
    if (val[i] < val[best]) best = i;
  return {pts[best], val[best]};
}

}  // namespace glassmap::sensor
