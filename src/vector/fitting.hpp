#pragma once
// Private to vector/: the CGAL-backed steps (region growing, least-squares line fits) behind a
// CGAL-free interface, so that CGAL is compiled in one translation unit (fitting.cpp) only.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "glassmap/core/pose2.hpp"

namespace glassmap::vector::detail {

/// Cell centres of one material with a unit normal each, and a dense index of the grid.
struct CellCloud {
  std::vector<Vec2> points;         ///< cell centres [m]
  std::vector<Vec2> normals;        ///< unit normals
  std::vector<double> seed_score;   ///< higher grows first; negative never seeds
  std::vector<std::int32_t> cell;   ///< linear grid index of each point
  std::vector<std::int32_t> index;  ///< [grid cell] point index or -1 (dense)
  int width = 0, height = 0;
  double resolution = 0.05;
  Vec2 origin_cells = Vec2::Zero();  ///< grid origin / resolution
};

/// Region growing parameters (see MaterialOptions).
struct GrowParams {
  double max_distance = 0.08;   ///< [m]
  double max_angle_deg = 20.0;  ///< [deg]
  double radius = 0.11;         ///< neighbour radius [m]
  std::size_t min_region = 3;   ///< smaller regions are left unassigned
};

/// CGAL::Shape_detection::Region_growing over the cloud with a grid neighbour query and a line
/// region whose normal stays the seed's until the region is elongated enough to fit one.
std::vector<std::vector<std::uint32_t>> growRegions(const CellCloud& cloud, const GrowParams& params);

/// Running second moments of a point set: the total-least-squares line and its residual in O(1)
/// per point, and sums of sets by addition (used for the split and merge criteria).
struct Moments {
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
  void add(const Vec2& p) {
    n += 1;
    sx += p.x();
    sy += p.y();
    sxx += p.x() * p.x();
    sxy += p.x() * p.y();
    syy += p.y() * p.y();
  }
  Moments& operator+=(const Moments& o) {
    n += o.n, sx += o.sx, sy += o.sy, sxx += o.sxx, sxy += o.sxy, syy += o.syy;
    return *this;
  }
  Moments operator-(const Moments& o) const {
    return {n - o.n, sx - o.sx, sy - o.sy, sxx - o.sxx, sxy - o.sxy, syy - o.syy};
  }
  Vec2 mean() const { return n > 0 ? Vec2(sx / n, sy / n) : Vec2::Zero(); }
  /// Covariance eigenvalues (major, minor) [m^2] and the major axis angle [rad].
  void eigen(double& l_max, double& l_min, double& angle) const {
    const Vec2 m = mean();
    const double cxx = sxx / n - m.x() * m.x(), cxy = sxy / n - m.x() * m.y(), cyy = syy / n - m.y() * m.y();
    const double h = 0.5 * (cxx + cyy), det = cxx * cyy - cxy * cxy;
    const double disc = std::sqrt(std::max(0.0, h * h - det));
    l_max = h + disc;
    l_min = std::max(0.0, h - disc);
    angle = 0.5 * std::atan2(2.0 * cxy, cxx - cyy);
  }
  /// Sum of squared distances to the total-least-squares line [m^2].
  double rss() const {
    if (n < 2) return 0.0;
    double l_max, l_min, angle;
    eigen(l_max, l_min, angle);
    return n * l_min;
  }
};

/// A fitted line: centroid and unit direction.
struct Line2 {
  Vec2 c = Vec2::Zero();
  Vec2 d = Vec2::UnitX();
};

/// CGAL::linear_least_squares_fitting_2 over the points of `ids` (at least 2 distinct points).
Line2 fitLine(const std::vector<Vec2>& points, const std::vector<std::uint32_t>& ids);

}  // namespace glassmap::vector::detail
