#pragma once
/// The likelihood-field model (Probabilistic Robotics 6.4; ROS AMCL's default): each beam's
/// end point scored by its distance to the nearest map segment, read from a precomputed grid.

#include <vector>

#include "glassmap/sensor/sensor_model.hpp"

namespace glassmap::sensor {

/// Distance [m] from points to the nearest segment, sampled at cell centres and read bilinearly.
class DistanceGrid {
 public:
  /// Distances to `segments` (those with use_glass false skip glass) up to max_dist [m].
  DistanceGrid(const VectorMap& map, bool use_glass, double resolution, double max_dist);
  /// Interpolated distance at p [m], max_dist outside the grid.
  double distance(const Vec2& p) const;
  /// Distance at p from the exact segment geometry (the reference for tests) [m], clamped to max_dist.
  double exactDistance(const Vec2& p) const;
  double resolution() const { return res_; }
  double maxDistance() const { return max_dist_; }
  Eigen::AlignedBox2d bounds() const;  ///< area covered [m]
  std::size_t cells() const { return d_.size(); }

 private:
  std::vector<MapSegment> segs_;
  std::vector<float> d_;
  Vec2 origin_ = Vec2::Zero();  // centre of cell (0, 0) [m]
  double res_ = 0.025, inv_res_ = 40.0, max_dist_ = 1.0;
  int nx_ = 0, ny_ = 0;
};

/// "field": p(z) = z_hit N(dist(end point); 0, sigma) + z_rand / z_max for z < z_max; a max reading
/// gets the constant mass z_max (it carries no information, as in AMCL). Integrates to 1 over
/// range for a beam meeting a lone wall at normal incidence, to about 1/cos(theta) at incidence
/// theta: it is a density over end points, not over ranges.
class FieldModel final : public SensorModel {
 public:
  FieldModel(const VectorMap& map, const SensorParams& params);
  std::string name() const override { return "field"; }
  double logLikelihood(const Pose2& T_map_laser, const Vec2& dir, double z,
                       double max_range) const override;
  double logLikelihood(const Pose2& T_map_laser, const BeamSet& beams) const override;
  const VectorMap& map() const override { return map_; }
  const DistanceGrid& grid() const { return grid_; }

 private:
  VectorMap map_;
  DistanceGrid grid_;
  double w_hit_ = 0, w_max_ = 0, w_rand_ = 0, sigma_ = 0.05;
};

}  // namespace glassmap::sensor
