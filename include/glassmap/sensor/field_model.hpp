#pragma once
/// The likelihood-field model (Probabilistic Robotics 6.4; ROS AMCL's default): each beam's
/// end point scored by its distance to the nearest map segment, read from a precomputed grid.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "glassmap/core/angles.hpp"
#include "glassmap/sensor/sensor_model.hpp"

namespace glassmap::sensor {

/// Distance [m] from points to the nearest segment, sampled at cell centres and read bilinearly.
///
/// Stored in square tiles, allocated only where some segment lies within max_dist: memory follows
/// the segments' length, not the map's bounding box (a stray segment far away costs a few tiles).
/// Cells of no tile are max_dist away from every segment.
class DistanceGrid {
 public:
  /// Distances to `segments` (those with use_glass false skip glass) up to max_dist [m].
  DistanceGrid(const VectorMap& map, bool use_glass, double resolution, double max_dist);
  /// Interpolated distance at p [m], max_dist outside the tiles.
  double distance(const Vec2& p) const;
  /// Distance at p from the exact segment geometry (the reference for tests) [m], clamped to max_dist.
  double exactDistance(const Vec2& p) const;
  double resolution() const { return res_; }
  double maxDistance() const { return max_dist_; }
  Eigen::AlignedBox2d bounds() const;                     ///< area the tiles may cover [m]
  std::size_t tiles() const { return tile_count_; }       ///< tiles allocated
  std::size_t samples() const { return values_.size(); }  ///< distances stored
  std::size_t bytes() const;                              ///< memory held [bytes]

 private:
  float* tileOf(int tx, int ty);  // allocates on first use
  std::vector<MapSegment> segs_;
  std::vector<std::int32_t> tile_index_;  // [ty * tiles_x_ + tx]: tile number, -1 = none
  std::vector<float> values_;             // tile k: (tile_ + 1)^2 samples from k * stride_
  std::size_t tile_count_ = 0;
  Vec2 origin_ = Vec2::Zero();  // centre of cell (0, 0) [m]
  double res_ = 0.025, inv_res_ = 40.0, max_dist_ = 1.0;
  int nx_ = 0, ny_ = 0;                        // samples along x and y
  int tile_ = 64, tiles_x_ = 0, tiles_y_ = 0;  // tile side [cells] (a power of two) and tile counts
  int tile_shift_ = 6;                         // log2(tile_)
  std::size_t stride_ = 0;                     // (tile_ + 1)^2
};

/// "field": p(z) = z_hit N(dist(end point); 0, sigma(z)) + z_rand / z_max for z < z_max; a max
/// reading gets the constant mass z_max (it carries no information, as in AMCL). sigma(z) =
/// hypot(sigma_hit, sigma_hit_rel z) is taken on a ladder of 16 steps per octave from sigma_hit
/// (within 2.2%), one table per step. Integrates to 1 over
/// range for a beam meeting a lone wall at normal incidence, to about 1/cos(theta) at incidence
/// theta: it is a density over end points, not over ranges.
class FieldModel final : public SensorModel {
 public:
  FieldModel(const VectorMap& map, const SensorParams& params);
  std::string name() const override { return "field"; }
  double logLikelihood(const Pose2& T_map_laser, const Vec2& dir, double z, double max_range) const override;
  double logLikelihood(const Pose2& T_map_laser, const BeamSet& beams) const override;
  void logLikelihoods(std::span<const Pose2> poses, const BeamSet& beams, double* out) const override;
  const VectorMap& map() const override { return map_; }
  void setParams(const SensorParams& params) override;
  const DistanceGrid& grid() const { return grid_; }

 private:
  void tabulate(const SensorParams& params);  // weights, sigma and the log-p table
  /// The ladder step of a reading z < z_max's sigma (0 when sigma does not grow with range).
  std::size_t level(double z) const;
  /// log(w_hit N(d; 0, sigma) + w_rand / max_range) at distance d, sigma that of ladder step
  /// `level`: from its table when max_range is the one it was built for, else computed.
  double logHit(double d, double max_range, std::size_t level) const;

  VectorMap map_;
  DistanceGrid grid_;
  double w_hit_ = 0, w_max_ = 0, w_rand_ = 0, sigma_ = 0.05, sigma_rel_ = 0.0;
  // log p of a reading against the end point's distance d, tabulated over [0, max_dist] and read
  // linearly: no exp or log per beam. The table's step (max_dist / 4095) keeps its error under
  // 1e-5 nats per beam at sigma 2 cm, 1 m max_dist (the curvature is at most 1 / sigma^2). One
  // table of kTableSize entries per ladder step, sigma of step k: level_sigma_[k].
  static constexpr std::size_t kTableSize = 4097;
  static constexpr double kLevelsPerOctave = 16.0;
  std::vector<double> table_, level_sigma_;
  double table_max_range_ = 0.0, table_inv_step_ = 0.0;
};

// The per-beam reads, inline: they are most of a likelihood-field update.
inline double DistanceGrid::distance(const Vec2& p) const {
  const double fx = (p.x() - origin_.x()) * inv_res_;
  const double fy = (p.y() - origin_.y()) * inv_res_;
  if (!(fx >= 0.0 && fy >= 0.0 && fx < nx_ - 1 && fy < ny_ - 1)) return max_dist_;
  const int i = static_cast<int>(fx), j = static_cast<int>(fy);
  const int tx = i >> tile_shift_, ty = j >> tile_shift_;
  const std::int32_t k =
      tile_index_[static_cast<std::size_t>(ty) * static_cast<std::size_t>(tiles_x_) + static_cast<std::size_t>(tx)];
  if (k < 0) return max_dist_;
  const double u = fx - i, v = fy - j;
  const float* c = &values_[static_cast<std::size_t>(k) * stride_ +
                            static_cast<std::size_t>(j - ty * tile_) * static_cast<std::size_t>(tile_ + 1) +
                            static_cast<std::size_t>(i - tx * tile_)];
  const float* n = c + (tile_ + 1);
  return (1 - v) * ((1 - u) * c[0] + u * c[1]) + v * ((1 - u) * n[0] + u * n[1]);
}

inline std::size_t FieldModel::level(double z) const {
  if (!(sigma_rel_ > 0)) return 0;
  const double steps = kLevelsPerOctave * std::log2(std::hypot(sigma_, sigma_rel_ * z) / sigma_);
  return std::min(static_cast<std::size_t>(std::lround(std::max(steps, 0.0))), level_sigma_.size() - 1);
}

inline double FieldModel::logHit(double d, double max_range, std::size_t level) const {
  if (max_range == table_max_range_) {
    // The grid never returns more than max_dist; the last entry repeats it for the read at the end.
    const double* table = &table_[level * kTableSize];
    const double f = std::min(d, grid_.maxDistance()) * table_inv_step_;
    const auto i = static_cast<std::size_t>(f);
    const double u = f - static_cast<double>(i);
    return table[i] + u * (table[i + 1] - table[i]);
  }
  const double sigma = level_sigma_[level], u = d / sigma;
  return std::log(w_hit_ * std::exp(-0.5 * u * u) / (std::sqrt(2.0 * kPi) * sigma) + w_rand_ / max_range);
}

}  // namespace glassmap::sensor
