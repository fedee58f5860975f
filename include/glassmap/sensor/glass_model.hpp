#pragma once
/// The paper's glass sensor model (sections 2.1-2.4). For a beam whose first surface is glass at
/// range d_g and incidence theta [deg] three modes:
///   direct reflection  P(direct|theta) = exp(-theta^2 / (2 sigma_dr^2)), z ~ N(d_g, sigma_z)
///   normal reflection  P(norm|theta) = exp(-lambda (90 - theta)),       z ~ N(d_g + d_o, sigma_z)
///   refraction         P(ref|theta) = max(0, 1 - P(norm) - P(direct)),   z ~ N(d_real + offset, sigma_z)
/// with d_o from the ray mirrored at the pane and d_real from the ray continued through it.
/// Beams whose first surface is a wall use the beam model.
///
/// Variant::Mixture ("glass"): the three weights normalised to sum 1 form the hit component of the
/// beam-model mixture (short, max and random terms kept): a proper density over [0, z_max].
/// Variant::Paper ("glass-paper"): the paper's inclusion-exclusion a1 + a2 + a3 - a1 a2 - a1 a3 -
/// a2 a3 of the weighted densities a_k, as written. Densities above 1 (sigma_z of a few cm) make
/// it negative; it is then floored at the random-reading density z_rand / z_max before the log,
/// which is also what a reading far from every mode gets.

#include "glassmap/geometry/ray_caster.hpp"
#include "glassmap/sensor/mixture.hpp"
#include "glassmap/sensor/sensor_model.hpp"

namespace glassmap::sensor {

/// Expected ranges of the three glass modes for one beam.
struct GlassModes {
  double d_g = 0;                                    ///< range to the pane [m]
  double theta_deg = 0;                              ///< incidence angle [deg]
  double w_direct = 0, w_normal = 0, w_refract = 0;  ///< the paper's P(mode | theta) [-]
  double e_normal = 0;                               ///< d_g + d_o [m]; +inf when the mirrored ray meets nothing
  double e_refract = 0;                              ///< d_real + offset [m]; +inf when the continued ray meets nothing
};

class GlassModel final : public SensorModel {
 public:
  enum class Variant { Mixture, Paper };
  GlassModel(const VectorMap& map, const SensorParams& params, Variant variant = Variant::Mixture);
  std::string name() const override { return variant_ == Variant::Paper ? "glass-paper" : "glass"; }
  double logLikelihood(const Pose2& T_map_laser, const Vec2& dir, double z, double max_range) const override;
  double logLikelihood(const Pose2& T_map_laser, const BeamSet& beams) const override;
  void logLikelihoods(std::span<const Pose2> poses, const BeamSet& beams, double* out) const override;
  const VectorMap& map() const override { return caster_.map(); }
  void setParams(const SensorParams& params) override;

  /// The modes for a pane hit `hit` by the ray origin + s dir (casts the mirrored and continued rays).
  GlassModes modes(const Vec2& origin, const Vec2& dir, const RayHit& hit, double max_range) const;

 private:
  double probability(const Vec2& origin, const Vec2& dir, double z, double max_range) const;
  // The pieces modes() and probability() are made of, shared by the one-ray path and the batch
  // path (glass_batch.cpp, which casts the rays of many beams together with RayCaster::castBatch).
  /// d_g, theta and the three weights for a pane hit (hit.incidence set); e_* left +inf.
  GlassModes weights(const RayHit& hit) const;
  /// Direction of the ray `dir` mirrored at segment `pane`.
  Vec2 mirrored(std::int32_t pane, const Vec2& dir) const;
  /// The ray continued through panes: where its next cast starts, distance and offset so far.
  struct Transmitted {
    Vec2 o;
    double travelled, offset;
    std::int32_t skip;
    int k;  ///< number of the next cast, 1..max_panes
  };
  Transmitted transmitted(const GlassModes& m, const RayHit& hit, const Vec2& p, const Vec2& dir) const;
  /// Range elongation [m] of the ray along `dir` through pane `pane` (or the fixed offset).
  double elongation(std::int32_t pane, const Vec2& dir) const;
  /// Takes the transmitted ray's cast `next` (range, segment, material) along `dir`; true when the
  /// ray goes on through another pane (t updated), false when it ends (e_refract set if it met a
  /// wall or its last pane, left +inf if it met nothing).
  bool goesOn(Transmitted& t, const RayHit& next, const Vec2& dir, double& e_refract) const;
  /// p(z) of a beam whose first surface is a pane, from its modes, with the mixture of its reading
  /// (mix_.at(z)) and short_numerator = mix.shortNumerator(z).
  double fromModes(const Mixture& mix, const GlassModes& m, double z, double max_range, double short_numerator) const;

  RayCaster caster_;
  /// Per segment, what does not depend on the ray: b - a, its unit direction and length, thickness.
  struct Pane {
    Vec2 d, t;
    double len, thickness;
  };
  std::vector<Pane> panes_;
  std::vector<Material> materials_;  ///< per segment, compact (the batch path's lookups)
  Mixture mix_;
  Variant variant_;
};

}  // namespace glassmap::sensor
