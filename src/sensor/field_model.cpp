#include "glassmap/sensor/field_model.hpp"

#include <algorithm>
#include <cmath>

#include "glassmap/core/error.hpp"

namespace glassmap::sensor {
DistanceGrid::DistanceGrid(const VectorMap& map, bool use_glass, double resolution, double max_dist)
    : res_(resolution), inv_res_(1.0 / resolution), max_dist_(max_dist) {
  if (!(resolution > 0) || !(max_dist > 0))
    throw Error("distance grid resolution and max distance must be positive", {}, 0, "field_resolution");
  for (const MapSegment& s : map.segments)
    if (use_glass || s.material == Material::Wall) segs_.push_back(s);
  Eigen::AlignedBox2d box;
  for (const MapSegment& s : segs_) {
    box.extend(s.a);
    box.extend(s.b);
  }
  if (box.isEmpty()) box.extend(Vec2::Zero());
  // Cover the segments plus max_dist and one cell so that bilinear reads stay inside.
  const Vec2 lo = box.min() - Vec2::Constant(max_dist + resolution);
  const Vec2 hi = box.max() + Vec2::Constant(max_dist + resolution);
  nx_ = static_cast<int>(std::ceil((hi.x() - lo.x()) * inv_res_)) + 1;
  ny_ = static_cast<int>(std::ceil((hi.y() - lo.y()) * inv_res_)) + 1;
  origin_ = lo;
  d_.assign(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_), static_cast<float>(max_dist));
  // Each segment updates only the cells within max_dist of its bounding box: the cost grows with
  // the segments' length, not with the floor's area.
  for (const MapSegment& s : segs_) {
    const Vec2 smin = s.a.cwiseMin(s.b) - Vec2::Constant(max_dist);
    const Vec2 smax = s.a.cwiseMax(s.b) + Vec2::Constant(max_dist);
    const int i0 = std::max(0, static_cast<int>(std::floor((smin.x() - origin_.x()) * inv_res_)));
    const int j0 = std::max(0, static_cast<int>(std::floor((smin.y() - origin_.y()) * inv_res_)));
    const int i1 = std::min(nx_ - 1, static_cast<int>(std::ceil((smax.x() - origin_.x()) * inv_res_)));
    const int j1 = std::min(ny_ - 1, static_cast<int>(std::ceil((smax.y() - origin_.y()) * inv_res_)));
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const Vec2 c = origin_ + res_ * Vec2(i, j);
        float& cell = d_[static_cast<std::size_t>(j) * static_cast<std::size_t>(nx_) + static_cast<std::size_t>(i)];
        cell = std::min(cell, static_cast<float>(s.distanceTo(c)));
      }
  }
}

Eigen::AlignedBox2d DistanceGrid::bounds() const {
  Eigen::AlignedBox2d b;
  b.extend(origin_);
  b.extend(origin_ + res_ * Vec2(nx_ - 1, ny_ - 1));
  return b;
}

double DistanceGrid::distance(const Vec2& p) const {
  const double fx = (p.x() - origin_.x()) * inv_res_;
  const double fy = (p.y() - origin_.y()) * inv_res_;
  if (!(fx >= 0.0 && fy >= 0.0 && fx < nx_ - 1 && fy < ny_ - 1)) return max_dist_;
  const int i = static_cast<int>(fx), j = static_cast<int>(fy);
  const double u = fx - i, v = fy - j;
  const float* c = &d_[static_cast<std::size_t>(j) * static_cast<std::size_t>(nx_) + static_cast<std::size_t>(i)];
  const float* n = c + nx_;
  return (1 - v) * ((1 - u) * c[0] + u * c[1]) + v * ((1 - u) * n[0] + u * n[1]);
}

double DistanceGrid::exactDistance(const Vec2& p) const {
  double best = max_dist_;
  for (const MapSegment& s : segs_) best = std::min(best, s.distanceTo(p));
  return best;
}

FieldModel::FieldModel(const VectorMap& map, const SensorParams& params)
    : map_(map),
      grid_(map, params.glass_as == GlassAs::Opaque, params.field_resolution, params.field_max_dist),
      sigma_(params.sigma_hit) {
  if (!(params.sigma_hit > 0)) throw Error("sigma_hit must be positive", {}, 0, "sigma_hit");
  if (!(params.z_rand > 0)) throw Error("z_rand must be positive", {}, 0, "z_rand");
  // The field model has no short-reading term (AMCL's neither): hit, max and random only.
  const double sum = params.z_hit + params.z_max + params.z_rand;
  w_hit_ = params.z_hit / sum;
  w_max_ = params.z_max / sum;
  w_rand_ = params.z_rand / sum;
}

double FieldModel::logLikelihood(const Pose2& T_map_laser, const Vec2& dir, double z,
                                 double max_range) const {
  if (z >= max_range) return std::log(std::max(w_max_, 1e-12));
  const double d = grid_.distance(T_map_laser.t + z * dir);
  const double u = d / sigma_;
  return std::log(w_hit_ * std::exp(-0.5 * u * u) / (std::sqrt(2.0 * kPi) * sigma_) + w_rand_ / max_range);
}

double FieldModel::logLikelihood(const Pose2& T_map_laser, const BeamSet& beams) const {
  const Eigen::Matrix2d R = T_map_laser.rotation();
  const double k = w_hit_ / (std::sqrt(2.0 * kPi) * sigma_), rand = w_rand_ / beams.max_range;
  const double h = -0.5 / (sigma_ * sigma_);
  const double log_max = std::log(std::max(w_max_, 1e-12));
  double sum = 0.0;
  for (std::size_t i = 0; i < beams.size(); ++i) {
    if (beams.ranges[i] >= beams.max_range) {
      sum += log_max;
      continue;
    }
    const double d = grid_.distance(T_map_laser.t + R * beams.points[i]);
    sum += std::log(k * std::exp(h * d * d) + rand);
  }
  return sum;
}

}  // namespace glassmap::sensor
