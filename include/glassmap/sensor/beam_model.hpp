#pragma once
/// The standard beam model (Probabilistic Robotics, table 6.1): hit, short, max and random
/// readings, the expected range from a ray cast. Glass is opaque or invisible (SensorParams).

#include "glassmap/geometry/ray_caster.hpp"
#include "glassmap/sensor/mixture.hpp"
#include "glassmap/sensor/sensor_model.hpp"

namespace glassmap::sensor {

/// "beam": p(z) = z_hit p_hit + z_short p_short + z_max 1[z = z_max] + z_rand / z_max.
class BeamModel final : public SensorModel {
 public:
  BeamModel(const VectorMap& map, const SensorParams& params);
  std::string name() const override { return "beam"; }
  double logLikelihood(const Pose2& T_map_laser, const Vec2& dir, double z, double max_range) const override;
  double logLikelihood(const Pose2& T_map_laser, const BeamSet& beams) const override;
  void logLikelihoods(std::span<const Pose2> poses, const BeamSet& beams, double* out) const override;
  const VectorMap& map() const override { return map_; }
  void setParams(const SensorParams& params) override;

 private:
  double probability(const Vec2& origin, const Vec2& dir, double z, double max_range) const;
  VectorMap map_;     // the full map (glass included)
  RayCaster caster_;  // over the map, or its walls only when glass is invisible
  Mixture mix_;
};

}  // namespace glassmap::sensor
