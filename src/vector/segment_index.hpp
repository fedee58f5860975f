#pragma once
// Private to vector/: segments bucketed by the square cells their box (grown by a reach) covers,
// for the steps that look up the segments near a return (scan_fit.cpp, scan_clutter.cpp).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "glassmap/geometry/vector_map.hpp"

namespace glassmap::vector::detail {

// Segments bucketed by the square cells their box (grown by `reach`) covers.
class SegmentIndex {
 public:
  // `segs`: pointers to the segments (MapSegment* or const MapSegment*), indexed by position.
  template <class SegmentPtr>
  SegmentIndex(const std::vector<SegmentPtr>& segs, double reach) {
    Eigen::AlignedBox2d box;
    for (const auto& s : segs) box.extend(s->a), box.extend(s->b);
    if (box.isEmpty()) return;
    origin_ = box.min() - Vec2::Constant(reach);
    const Vec2 size = box.sizes() + Vec2::Constant(2.0 * reach);
    // Cells of 0.5 m, coarser on huge extents (a stray segment far away) so the index stays small.
    cell_ = std::max(0.5, std::sqrt(size.x() * size.y() / 4e6));
    nx_ = static_cast<std::size_t>(size.x() / cell_) + 1;
    ny_ = static_cast<std::size_t>(size.y() / cell_) + 1;
    cells_.resize(nx_ * ny_);
    for (std::size_t k = 0; k < segs.size(); ++k) {
      const Vec2 lo = segs[k]->a.cwiseMin(segs[k]->b) - Vec2::Constant(reach);
      const Vec2 hi = segs[k]->a.cwiseMax(segs[k]->b) + Vec2::Constant(reach);
      const auto [x0, y0] = cellOf(lo);
      const auto [x1, y1] = cellOf(hi);
      for (std::size_t y = y0; y <= y1; ++y)
        for (std::size_t x = x0; x <= x1; ++x) cells_[y * nx_ + x].push_back(static_cast<std::uint32_t>(k));
    }
  }
  // The segments whose grown box may hold p (none outside the index).
  const std::vector<std::uint32_t>* near(const Vec2& p) const {
    if (cells_.empty()) return nullptr;
    const Vec2 q = (p - origin_) / cell_;
    if (!(q.x() >= 0 && q.y() >= 0 && q.x() < static_cast<double>(nx_) && q.y() < static_cast<double>(ny_)))
      return nullptr;
    return &cells_[static_cast<std::size_t>(q.y()) * nx_ + static_cast<std::size_t>(q.x())];
  }

 private:
  std::pair<std::size_t, std::size_t> cellOf(const Vec2& p) const {
    const Vec2 q = ((p - origin_) / cell_).cwiseMax(0.0);
    return {std::min(static_cast<std::size_t>(q.x()), nx_ - 1), std::min(static_cast<std::size_t>(q.y()), ny_ - 1)};
  }
  Vec2 origin_ = Vec2::Zero();
  double cell_ = 0.5;
  std::size_t nx_ = 0, ny_ = 0;
  std::vector<std::vector<std::uint32_t>> cells_;
};

}  // namespace glassmap::vector::detail
