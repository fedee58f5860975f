#pragma once
/// Per-beam laser likelihood models p(z | x, m) against a VectorMap, behind one interface and
/// picked by name: "beam", "field", "glass" (default) and "glass-paper" (paper section 2.4).
/// Everything is returned as a natural log-likelihood.

#include <cmath>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "glassmap/core/laser_scan.hpp"
#include "glassmap/core/pose2.hpp"
#include "glassmap/core/sensor_profile.hpp"
#include "glassmap/geometry/vector_map.hpp"

namespace glassmap::sensor {

/// How a glass-unaware model (beam, field) sees the map's glass.
enum class GlassAs { Opaque, Invisible };

/// "opaque" / "invisible"; parseGlassAs throws Error otherwise.
std::string_view toString(GlassAs g);
GlassAs parseGlassAs(std::string_view s);

/// Parameters of the models. The mixture weights z_* are normalised by the models.
struct SensorParams {
  double max_range = 30.0;             ///< sensor maximum range z_max [m] (a log's scans override it)
  double sigma_hit = 0.05;             ///< std dev of a measured range around the expected one, sigma_z [m]
  double sigma_hit_rel = 0.0;          ///< its growth with the reading z: sigma(z) = hypot(sigma_hit,
                                       ///< sigma_hit_rel z) per beam (beam, glass and field models) [-]
  double z_hit = 0.85;                 ///< weight of the hit (measurement) component [-]
  double z_short = 0.05;               ///< weight of unexpected short readings (people, clutter) [-]
  double z_max = 0.05;                 ///< weight of max-range readings (missed echoes) [-]
  double z_rand = 0.05;                ///< weight of uniformly random readings [-]
  double lambda_short = 0.2;           ///< rate of the short-reading exponential [1/m]
  GlassAs glass_as = GlassAs::Opaque;  ///< beam/field: what glass is to them
  // Glass model (paper 2.1-2.3).
  double direct_sigma_deg =
      1.7320508075688772;       ///< direct-reflection lobe sigma_dr [deg] (paper: sigma_dr^2 = 3 deg^2)
  double direct_peak = 1.0;     ///< P(direct) at normal incidence (the paper's lobe: 1) [-]
  double direct_floor = 0.0;    ///< P(direct) at any angle: w_direct = floor + (peak - floor) lobe [-]
  double lambda_normal = 0.09;  ///< rate of the normal-reflection weight [1/deg]
  double normal_floor = 0.0;    ///< w_normal = floor + (1 - floor) exp(-lambda (90 - theta)) [-]
  double glass_index = 1.5;     ///< refractive index used for the refraction offset [-]
  double offset = -1.0;         ///< refraction offset per pane [m]; < 0: the physical elongation
                                ///< t (n / cos theta_t - 1 / cos theta_i) of each pane crossed
  int max_panes = 4;            ///< panes the transmitted ray is followed through
  // Field model.
  double field_resolution = 0.025;  ///< cell size of the precomputed distance grid [m]
  double field_max_dist = 1.0;      ///< distances are clamped to this [m]
};

/// Beams of one scan prepared for evaluation: angles in the laser frame, unit directions, ranges.
struct BeamSet {
  std::vector<double> angles;  ///< beam angle in the laser frame [rad]
  std::vector<Vec2> dirs;      ///< (cos, sin) of angles
  std::vector<double> ranges;  ///< measured range z [m]; >= max_range means a max reading
  std::vector<Vec2> points;    ///< z * dir: the end point in the laser frame [m]
  double max_range = 30.0;     ///< z_max of the scan [m]
  std::size_t size() const { return ranges.size(); }
};

/// The range sigma of a reading z [m] (sigma_hit, grown with range by sigma_hit_rel).
inline double sigmaAt(const SensorParams& p, double z) {
  return p.sigma_hit_rel > 0 ? std::hypot(p.sigma_hit, p.sigma_hit_rel * z) : p.sigma_hit;
}

/// The models' parameters from a sensor profile (sensor/calibrate.hpp): the glass lobe (peak,
/// sigma, floor), the reflection rate and floor, the mixture weights and lambda_short, and the
/// range noise beam by beam: sigma_hit = max(the profile's constant part sigma_0, min_sigma_hit),
/// sigma_hit_rel = its growth with range (a laser whose noise grows with range, hypot(sigma_0,
/// rel r), is wide at the far beams and sharp at the near ones, as it reads). The floor: a
/// floorplan is never drawn to the millimetre, and a likelihood sharper than the map is true to
/// starves the particle filter.
inline constexpr double kMinProfileSigmaHit = 0.02;  ///< paramsFromProfile's default floor [m]
SensorParams paramsFromProfile(const SensorProfile& profile, SensorParams base = {},
                               double min_sigma_hit = kMinProfileSigmaHit);

/// Picks `count` beams spread evenly over the scan (all when count <= 0 or >= the scan's size).
/// A no-return reading (kNoReturn) becomes a max reading.
BeamSet makeBeamSet(const LaserScan& scan, int count);

/// One beam model: log p(z | x, m) per beam, summed over a scan.
class SensorModel {
 public:
  virtual ~SensorModel() = default;
  /// Model name as picked on the command line.
  virtual std::string name() const = 0;
  /// log p(z | T_map_laser, m) of one beam from the laser's origin along unit direction `dir`
  /// (map frame) reading z [m]; z >= max_range is a max reading: the log of its probability mass.
  virtual double logLikelihood(const Pose2& T_map_laser, const Vec2& dir, double z, double max_range) const = 0;
  /// Sum over the beams of logLikelihood.
  virtual double logLikelihood(const Pose2& T_map_laser, const BeamSet& beams) const;
  /// logLikelihood(poses[j], beams) into out[j] for every pose, bit for bit as one call per pose;
  /// a model may order the work beam-major (all poses' end points of one beam, then the next), which
  /// keeps the map reads of nearby particles together in cache.
  virtual void logLikelihoods(std::span<const Pose2> poses, const BeamSet& beams, double* out) const;
  /// The same for a beam at `angle` [rad] in the laser frame.
  double beamLogLikelihood(const Pose2& T_map_laser, double angle, double z, double max_range) const;
  /// The map the model was built on.
  virtual const VectorMap& map() const = 0;
  /// The parameters in use.
  const SensorParams& params() const { return params_; }
  /// Replaces the parameters that do not depend on the map (noise, mixture weights, glass lobe and
  /// reflection, refraction): what a calibration against the data changes. What shaped the model's
  /// map at construction stays (glass_as, the likelihood field's grid resolution and reach).
  virtual void setParams(const SensorParams& params) = 0;

 protected:
  explicit SensorModel(const SensorParams& params) : params_(params) {}
  SensorParams params_;
};

/// Model names accepted by makeSensorModel.
std::vector<std::string> sensorModelNames();
/// Builds a model by name over a copy of `map`; throws Error for an unknown name.
std::unique_ptr<SensorModel> makeSensorModel(std::string_view name, const VectorMap& map,
                                             const SensorParams& params = {});

}  // namespace glassmap::sensor
