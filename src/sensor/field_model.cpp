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
    if ((use_glass || s.material == Material::Wall) && s.a.allFinite() && s.b.allFinite()) segs_.push_back(s);
  Eigen::AlignedBox2d box;
  for (const MapSegment& s : segs_) {
    box.extend(s.a);
    box.extend(s.b);
  }
  if (box.isEmpty()) box.extend(Vec2::Zero());
  // Cover the segments plus max_dist and one cell so that bilinear reads stay inside.
  const Vec2 lo = box.min() - Vec2::Constant(max_dist + resolution);
  const Vec2 hi = box.max() + Vec2::Constant(max_dist + resolution);
  const double nx = std::ceil((hi.x() - lo.x()) * inv_res_) + 1, ny = std::ceil((hi.y() - lo.y()) * inv_res_) + 1;
  if (!(nx < 1e9 && ny < 1e9))
    throw Error("the map spans more than 1e9 distance cells: a coordinate is absurdly far away", {}, 0, "segments");
  nx_ = static_cast<int>(nx);
  ny_ = static_cast<int>(ny);
  origin_ = lo;
  // Tiles of 64 cells, larger when the tile index would pass 4M entries (16 MB) on a huge extent.
  constexpr double kMaxIndex = 4.0 * 1024 * 1024;
  // A power of two, so that the per-read tile number is a shift, not a division.
  const int wanted = std::max(64, static_cast<int>(std::ceil(std::sqrt(double(nx_) * double(ny_) / kMaxIndex))));
  tile_shift_ = 6;
  while ((1 << tile_shift_) < wanted) ++tile_shift_;
  tile_ = 1 << tile_shift_;
  tiles_x_ = (nx_ - 1 + tile_ - 1) / tile_ + 1;
  tiles_y_ = (ny_ - 1 + tile_ - 1) / tile_ + 1;
  stride_ = static_cast<std::size_t>(tile_ + 1) * static_cast<std::size_t>(tile_ + 1);
  // Refuse, before allocating, a grid over 1e9 samples (4 GB): segments of absurd total length.
  double samples = 0.0;
  for (const MapSegment& s : segs_) {
    const Vec2 ext = (s.a - s.b).cwiseAbs() + Vec2::Constant(2 * max_dist + 2 * tile_ * resolution);
    samples += std::min(ext.x() * inv_res_ * ext.y() * inv_res_, double(nx_) * double(ny_));
  }
  if (samples > 1e9)
    throw Error("the distance grid would need about " + std::to_string(static_cast<long long>(samples * 4 / 1e9)) +
                    " GB (over 1e9 cells of " + std::to_string(resolution) + " m): segments of implausible length",
                {}, 0, "segments");
  tile_index_.assign(static_cast<std::size_t>(tiles_x_) * static_cast<std::size_t>(tiles_y_), -1);
  // Each segment updates only the samples within max_dist of its bounding box: the cost and the
  // memory grow with the segments' length, not with the floor's area. A tile holds samples
  // tx * tile_ .. tx * tile_ + tile_ (one shared with its neighbour) so bilinear reads stay in it.
  for (const MapSegment& s : segs_) {
    const Vec2 smin = s.a.cwiseMin(s.b) - Vec2::Constant(max_dist);
    const Vec2 smax = s.a.cwiseMax(s.b) + Vec2::Constant(max_dist);
    const int i0 = std::max(0, static_cast<int>(std::floor((smin.x() - origin_.x()) * inv_res_)));
    const int j0 = std::max(0, static_cast<int>(std::floor((smin.y() - origin_.y()) * inv_res_)));
    const int i1 = std::min(nx_ - 1, static_cast<int>(std::ceil((smax.x() - origin_.x()) * inv_res_)));
    const int j1 = std::min(ny_ - 1, static_cast<int>(std::ceil((smax.y() - origin_.y()) * inv_res_)));
    for (int ty = std::max(0, (j0 - 1) / tile_); ty <= std::min(tiles_y_ - 1, j1 / tile_); ++ty)
      for (int tx = std::max(0, (i0 - 1) / tile_); tx <= std::min(tiles_x_ - 1, i1 / tile_); ++tx) {
        const int ta = std::max(i0, tx * tile_), tb = std::min(i1, tx * tile_ + tile_);
        const int ua = std::max(j0, ty * tile_), ub = std::min(j1, ty * tile_ + tile_);
        if (ta > tb || ua > ub) continue;
        float* t = tileOf(tx, ty);
        for (int j = ua; j <= ub; ++j)
          for (int i = ta; i <= tb; ++i) {
            const Vec2 c = origin_ + res_ * Vec2(i, j);
            float& cell = t[static_cast<std::size_t>(j - ty * tile_) * static_cast<std::size_t>(tile_ + 1) +
                            static_cast<std::size_t>(i - tx * tile_)];
            cell = std::min(cell, static_cast<float>(s.distanceTo(c)));
          }
      }
  }
}

float* DistanceGrid::tileOf(int tx, int ty) {
  std::int32_t& k =
      tile_index_[static_cast<std::size_t>(ty) * static_cast<std::size_t>(tiles_x_) + static_cast<std::size_t>(tx)];
  if (k < 0) {
    k = static_cast<std::int32_t>(tile_count_++);
    values_.resize(tile_count_ * stride_, static_cast<float>(max_dist_));
  }
  return &values_[static_cast<std::size_t>(k) * stride_];
}

std::size_t DistanceGrid::bytes() const {
  return values_.capacity() * sizeof(float) + tile_index_.capacity() * sizeof(std::int32_t) +
         segs_.capacity() * sizeof(MapSegment);
}

Eigen::AlignedBox2d DistanceGrid::bounds() const {
  Eigen::AlignedBox2d b;
  b.extend(origin_);
  b.extend(origin_ + res_ * Vec2(nx_ - 1, ny_ - 1));
  return b;
}

double DistanceGrid::exactDistance(const Vec2& p) const {
  double best = max_dist_;
  for (const MapSegment& s : segs_) best = std::min(best, s.distanceTo(p));
  return best;
}

FieldModel::FieldModel(const VectorMap& map, const SensorParams& params)
    : SensorModel(params),
      map_(map),
      grid_(map, params.glass_as == GlassAs::Opaque, params.field_resolution, params.field_max_dist) {
  tabulate(params);
}

void FieldModel::setParams(const SensorParams& params) {
  SensorParams p = params;
  p.glass_as = params_.glass_as;  // the grid was built for these
  p.field_resolution = params_.field_resolution;
  p.field_max_dist = params_.field_max_dist;
  tabulate(p);
  params_ = p;
}

void FieldModel::tabulate(const SensorParams& params) {
  if (!(params.sigma_hit > 0)) throw Error("sigma_hit must be positive", {}, 0, "sigma_hit");
  if (!(params.z_rand > 0)) throw Error("z_rand must be positive", {}, 0, "z_rand");
  if (!(params.sigma_hit_rel >= 0) || !std::isfinite(params.sigma_hit_rel))
    throw Error("sigma_hit_rel must be zero or positive", {}, 0, "sigma_hit_rel");
  sigma_ = params.sigma_hit;
  sigma_rel_ = params.sigma_hit_rel;
  // The ladder: 16 steps per octave from sigma_hit up to the sigma at max range (at most 8 octaves).
  const double octaves = std::log2(std::hypot(sigma_, sigma_rel_ * params.max_range) / sigma_);
  const auto levels = static_cast<std::size_t>(std::ceil(std::min(octaves, 8.0) * kLevelsPerOctave)) + 1;
  level_sigma_.resize(levels);
  for (std::size_t k = 0; k < levels; ++k)
    level_sigma_[k] = sigma_ * std::exp2(static_cast<double>(k) / kLevelsPerOctave);
  // The field model has no short-reading term (AMCL's neither): hit, max and random only.
  const double sum = params.z_hit + params.z_max + params.z_rand;
  w_hit_ = params.z_hit / sum;
  w_max_ = params.z_max / sum;
  w_rand_ = params.z_rand / sum;
  table_max_range_ = params.max_range;
  table_inv_step_ = static_cast<double>(kTableSize - 2) / grid_.maxDistance();
  table_.resize(levels * kTableSize);
  const double rand = w_rand_ / params.max_range;
  for (std::size_t step = 0; step < levels; ++step) {
    const double sigma = level_sigma_[step];
    const double k = w_hit_ / (std::sqrt(2.0 * kPi) * sigma), h = -0.5 / (sigma * sigma);
    for (std::size_t i = 0; i < kTableSize; ++i) {
      const double d = std::min(static_cast<double>(i) / table_inv_step_, grid_.maxDistance());
      table_[step * kTableSize + i] = std::log(k * std::exp(h * d * d) + rand);
    }
  }
}

double FieldModel::logLikelihood(const Pose2& T_map_laser, const Vec2& dir, double z, double max_range) const {
  if (z >= max_range) return std::log(std::max(w_max_, 1e-12));
  return logHit(grid_.distance(T_map_laser.t + z * dir), max_range, level(z));
}

double FieldModel::logLikelihood(const Pose2& T_map_laser, const BeamSet& beams) const {
  const Eigen::Matrix2d R = T_map_laser.rotation();
  const double log_max = std::log(std::max(w_max_, 1e-12));
  double sum = 0.0;
  for (std::size_t i = 0; i < beams.size(); ++i) {
    if (beams.ranges[i] >= beams.max_range) {
      sum += log_max;
      continue;
    }
    sum += logHit(grid_.distance(T_map_laser.t + R * beams.points[i]), beams.max_range, level(beams.ranges[i]));
  }
  return sum;
}

void FieldModel::logLikelihoods(std::span<const Pose2> poses, const BeamSet& beams, double* out) const {
  // Beam-major: the end points of one beam from a cloud of nearby particles fall within a few
  // cells of each other, so the grid reads share cache lines. Each out[j] still sums its beams in
  // beam order, as logLikelihood(poses[j], beams) does.
  constexpr std::size_t kBlock = 64;
  const double log_max = std::log(std::max(w_max_, 1e-12));
  for (std::size_t j0 = 0; j0 < poses.size(); j0 += kBlock) {
    const std::size_t n = std::min(kBlock, poses.size() - j0);
    double c[kBlock], s[kBlock], sum[kBlock];
    for (std::size_t j = 0; j < n; ++j) {
      c[j] = std::cos(poses[j0 + j].theta);
      s[j] = std::sin(poses[j0 + j].theta);
      sum[j] = 0.0;
    }
    for (std::size_t i = 0; i < beams.size(); ++i) {
      if (beams.ranges[i] >= beams.max_range) {
        for (std::size_t j = 0; j < n; ++j) sum[j] += log_max;
        continue;
      }
      const Vec2& q = beams.points[i];
      const std::size_t lv = level(beams.ranges[i]);
      for (std::size_t j = 0; j < n; ++j) {
        const Pose2& T = poses[j0 + j];
        // As T.t + T.rotation() * q, operation for operation.
        const double rx = c[j] * q.x() + (-s[j]) * q.y(), ry = s[j] * q.x() + c[j] * q.y();
        const Vec2 p(T.t.x() + rx, T.t.y() + ry);
        sum[j] += logHit(grid_.distance(p), beams.max_range, lv);
      }
    }
    for (std::size_t j = 0; j < n; ++j) out[j0 + j] = sum[j];
  }
}

}  // namespace glassmap::sensor
