// Free space of the map for random particles (global initialisation, probes, injection).
#include <algorithm>
#include <cmath>
#include <string>

#include "glassmap/core/error.hpp"
#include "glassmap/localize/particle_filter.hpp"
#include "glassmap/sensor/field_model.hpp"

namespace glassmap::localize {

void ParticleFilter::collectFreeCells() {
  // Free space: cells of the map's bounding box at least free_clearance from every segment, and
  // within free_reach of some segment's box (a robot farther from everything sees nothing; a
  // stray segment far away must not fill the void between it and the building with cells).
  const VectorMap& map = model_.map();
  Eigen::AlignedBox2d box;
  for (const MapSegment& s : map.segments)
    if (s.a.allFinite() && s.b.allFinite()) {
      box.extend(s.a);
      box.extend(s.b);
    }
  if (box.isEmpty()) return;
  const sensor::DistanceGrid grid(map, true, free_cell_, std::max(opt_.free_clearance, free_cell_));
  // Coarse blocks within reach of a segment's box; at most 2048 a side.
  const double reach = std::max(opt_.free_reach, free_cell_);
  const Vec2 extent = box.max() - box.min();
  const double block = std::max({reach / 2.0, extent.x() / 2048.0, extent.y() / 2048.0});
  const int bx = std::max(1, static_cast<int>(std::ceil(extent.x() / block)) + 1);
  const int by = std::max(1, static_cast<int>(std::ceil(extent.y() / block)) + 1);
  std::vector<std::uint8_t> near(static_cast<std::size_t>(bx) * static_cast<std::size_t>(by), 0);
  auto blockOf = [&](double v, double lo, int n) {
    return std::clamp(static_cast<int>(std::floor((v - lo) / block)), 0, n - 1);
  };
  for (const MapSegment& s : map.segments) {
    if (!s.a.allFinite() || !s.b.allFinite()) continue;
    const Vec2 lo = s.a.cwiseMin(s.b) - Vec2::Constant(reach), hi = s.a.cwiseMax(s.b) + Vec2::Constant(reach);
    for (int j = blockOf(lo.y(), box.min().y(), by); j <= blockOf(hi.y(), box.min().y(), by); ++j)
      for (int i = blockOf(lo.x(), box.min().x(), bx); i <= blockOf(hi.x(), box.min().x(), bx); ++i)
        near[static_cast<std::size_t>(j) * static_cast<std::size_t>(bx) + static_cast<std::size_t>(i)] = 1;
  }
  // Cell centres x_k = min + (k + 1/2) * cell below max, row by row, in increasing x; only the
  // cells of blocks near a segment are visited.
  const Vec2 c0 = box.min() + Vec2::Constant(free_cell_ / 2);
  auto count = [&](double from, double to) {
    return from < to ? static_cast<long long>(std::ceil((to - from) / free_cell_)) : 0LL;
  };
  const long long nx = count(c0.x(), box.max().x()), ny = count(c0.y(), box.max().y());
  // Up to 4M cells a side the centres are accumulated step by step, as the full scan over the box
  // always did (bit for bit the same cells, so the same random particles); beyond, x0 + k * cell.
  constexpr long long kAccumulated = 4LL << 20;
  std::vector<double> xs, ys;
  if (nx <= kAccumulated)
    for (double x = c0.x(); x < box.max().x(); x += free_cell_) xs.push_back(x);
  if (ny <= kAccumulated)
    for (double y = c0.y(); y < box.max().y(); y += free_cell_) ys.push_back(y);
  auto centre = [&](const std::vector<double>& acc, double first, long long k) {
    return k < static_cast<long long>(acc.size()) ? acc[static_cast<std::size_t>(k)]
                                                  : first + static_cast<double>(k) * free_cell_;
  };
  // At most 50M cells (800 MB): a map whose segments reach further is refused, not swapped.
  constexpr double kMaxFreeCells = 50e6;
  double estimate = 0.0;
  for (int j = 0; j < by; ++j)
    for (int i = 0; i < bx; ++i)
      estimate += near[static_cast<std::size_t>(j) * static_cast<std::size_t>(bx) + static_cast<std::size_t>(i)];
  estimate *= (block / free_cell_) * (block / free_cell_);
  if (estimate > kMaxFreeCells)
    throw Error("the map's free space within " + std::to_string(static_cast<int>(reach)) +
                    " m of its segments is about " + std::to_string(static_cast<long long>(estimate / 1e6)) +
                    "M cells of " + std::to_string(free_cell_) +
                    " m (limit 50M): segments spread over an implausible area",
                {}, 0, "segments");
  for (int j = 0; j < by; ++j) {
    const std::size_t row = static_cast<std::size_t>(j) * static_cast<std::size_t>(bx);
    if (std::find(near.begin() + static_cast<std::ptrdiff_t>(row),
                  near.begin() + static_cast<std::ptrdiff_t>(row + static_cast<std::size_t>(bx)),
                  1) == near.begin() + static_cast<std::ptrdiff_t>(row + static_cast<std::size_t>(bx)))
      continue;
    const long long ky0 = std::max(0LL, static_cast<long long>(std::floor(j * block / free_cell_)) - 2);
    const long long ky1 = std::min(ny, static_cast<long long>(std::ceil((j + 1) * block / free_cell_)) + 2);
    for (long long ky = ky0; ky < ky1; ++ky) {
      const double y = centre(ys, c0.y(), ky);
      if (!(y < box.max().y()) || blockOf(y, box.min().y(), by) != j) continue;
      for (int i = 0; i < bx; ++i) {
        if (!near[row + static_cast<std::size_t>(i)]) continue;
        const long long k0 = std::max(0LL, static_cast<long long>(std::floor(i * block / free_cell_)) - 2);
        const long long k1 = std::min(nx, static_cast<long long>(std::ceil((i + 1) * block / free_cell_)) + 2);
        for (long long k = k0; k < k1; ++k) {
          const double x = centre(xs, c0.x(), k);
          if (!(x < box.max().x()) || blockOf(x, box.min().x(), bx) != i) continue;
          if (grid.distance({x, y}) >= opt_.free_clearance) free_cells_.emplace_back(x, y);
        }
      }
    }
  }
}

Pose2 ParticleFilter::randomFreePose() {
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const double heading = (2.0 * u01(rng_) - 1.0) * kPi;
  if (free_cells_.empty()) {
    const Eigen::AlignedBox2d box = model_.map().bounds();
    if (box.isEmpty()) return {0.0, 0.0, heading};
    return {box.min() + (box.max() - box.min()).cwiseProduct(Vec2(u01(rng_), u01(rng_))), heading};
  }
  std::uniform_int_distribution<std::size_t> pick(0, free_cells_.size() - 1);
  const Vec2 c = free_cells_[pick(rng_)];
  return {c + free_cell_ * Vec2(u01(rng_) - 0.5, u01(rng_) - 0.5), heading};
}

}  // namespace glassmap::localize
