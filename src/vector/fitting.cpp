// The only translation unit of vector/ that includes CGAL (it dominates compile time).
#include "fitting.hpp"

#include <CGAL/Shape_detection/Region_growing/Region_growing.h>
#include <CGAL/linear_least_squares_fitting_2.h>
#include <CGAL/property_map.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "glassmap/core/angles.hpp"
#include "glassmap/geometry/cgal.hpp"

namespace glassmap::vector::detail {
namespace {

// CGAL RegionGrowing NeighborQuery: the cloud's points whose cells lie within the radius,
// found through the dense grid index (constant time per neighbour, no kd-tree to build).
class GridNeighbourQuery {
 public:
  GridNeighbourQuery(const CellCloud& cloud, double radius) : cloud_(cloud) {
    const int r = static_cast<int>(std::floor(radius / cloud.resolution));
    const double r2 = (radius / cloud.resolution) * (radius / cloud.resolution);
    for (int dy = -r; dy <= r; ++dy)
      for (int dx = -r; dx <= r; ++dx)
        if ((dx != 0 || dy != 0) && dx * dx + dy * dy <= r2 + 1e-9) offsets_.push_back({dx, dy});
  }

  void operator()(std::size_t query, std::vector<std::size_t>& neighbours) const {
    const int c = cloud_.cell[query];
    const int x = c % cloud_.width, y = c / cloud_.width;
    for (const auto& [dx, dy] : offsets_) {
      const int nx = x + dx, ny = y + dy;
      if (nx < 0 || ny < 0 || nx >= cloud_.width || ny >= cloud_.height) continue;
      const std::int32_t j = cloud_.index[static_cast<std::size_t>(ny) * cloud_.width + nx];
      if (j >= 0) neighbours.push_back(static_cast<std::size_t>(j));
    }
  }

 private:
  const CellCloud& cloud_;
  std::vector<std::pair<int, int>> offsets_;
};

// CGAL RegionType: a line region. A cell joins when it lies within max_distance of the region's
// line and its normal is within max_angle of the line's normal. Unlike CGAL's
// Least_squares_line_fit_region, the line keeps the seed's normal until the region is elongated
// (a handful of cells across a thick wall has no reliable direction), and is then refitted from
// running moments instead of from all points at every step.
class LineRegion {
 public:
  LineRegion(const CellCloud& cloud, const GrowParams& p)
      : cloud_(cloud),
        max_distance_(p.max_distance),
        cos_max_angle_(std::cos(deg2rad(p.max_angle_deg))),
        min_region_(p.min_region) {}

  bool is_part_of_region(std::size_t, std::size_t query, const std::vector<std::size_t>&) const {
    const Vec2& p = cloud_.points[query];
    return std::abs(normal_.dot(p - centre_)) <= max_distance_ &&
           std::abs(cloud_.normals[query].dot(normal_)) >= cos_max_angle_;
  }

  bool is_valid_region(const std::vector<std::size_t>& region) const { return region.size() >= min_region_; }

  void update(const std::vector<std::size_t>& region) {
    if (region.size() == 1) {
      moments_ = {};
      accumulated_ = 0;
      centre_ = cloud_.points[region[0]];
      normal_ = cloud_.normals[region[0]];
    }
    for (; accumulated_ < region.size(); ++accumulated_) moments_.add(cloud_.points[region[accumulated_]]);
    if (moments_.n < 3) return;
    double l_max, l_min, angle;
    moments_.eigen(l_max, l_min, angle);
    // Elongated: the long axis spreads at least 2x the short one, over 1.5 cells or more.
    const double res = cloud_.resolution;
    if (l_max < 4.0 * l_min || l_max < 2.25 * res * res) return;
    const Vec2 d(std::cos(angle), std::sin(angle));
    normal_ = Vec2(-d.y(), d.x());
    centre_ = moments_.mean();
  }

 private:
  const CellCloud& cloud_;
  double max_distance_, cos_max_angle_;
  std::size_t min_region_;
  Moments moments_;
  std::size_t accumulated_ = 0;
  Vec2 centre_ = Vec2::Zero();
  Vec2 normal_ = Vec2::UnitY();
};

}  // namespace

std::vector<std::vector<std::uint32_t>> growRegions(const CellCloud& cloud, const GrowParams& params) {
  std::vector<std::vector<std::uint32_t>> out;
  const std::size_t n = cloud.points.size();
  if (n == 0) return out;
  // Seeds in decreasing score; cells with a negative score never seed (they may still join).
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return cloud.seed_score[a] > cloud.seed_score[b]; });
  for (std::size_t& i : order)
    if (cloud.seed_score[i] < 0) i = std::size_t(-1);
  const auto seed_map = CGAL::make_property_map(order);

  GridNeighbourQuery neighbours(cloud, params.radius);
  LineRegion region(cloud, params);
  CGAL::Shape_detection::Region_growing<std::vector<Vec2>, GridNeighbourQuery, LineRegion, decltype(seed_map)> growing(
      cloud.points, neighbours, region, seed_map);
  std::vector<std::vector<std::size_t>> regions;
  growing.detect(std::back_inserter(regions));
  out.reserve(regions.size());
  for (const auto& r : regions) out.emplace_back(r.begin(), r.end());
  return out;
}

Line2 fitLine(const std::vector<Vec2>& points, const std::vector<std::uint32_t>& ids) {
  std::vector<CgalPoint2> pts;
  pts.reserve(ids.size());
  for (const std::uint32_t i : ids) pts.push_back(toCgal(points[i]));
  CgalKernel::Line_2 line;
  CgalPoint2 centroid;
  CGAL::linear_least_squares_fitting_2(pts.begin(), pts.end(), line, centroid, CGAL::Dimension_tag<0>());
  const auto dir = line.to_vector();
  Line2 out;
  out.c = fromCgal(centroid);
  out.d = Vec2(CGAL::to_double(dir.x()), CGAL::to_double(dir.y())).normalized();
  return out;
}

}  // namespace glassmap::vector::detail
