#pragma once
/// Monte Carlo localization: particles over laser poses in the map frame, odometry motion model,
/// a SensorModel, low-variance resampling when the effective sample size drops, KLD-sampling
/// adaptive particle count and augmented-MCL random-particle injection (Probabilistic Robotics
/// tables 4.4, 8.3, 8.4).

#include <cstdint>
#include <random>
#include <vector>

#include "glassmap/geometry/ray_caster.hpp"
#include "glassmap/localize/motion_model.hpp"
#include "glassmap/sensor/sensor_model.hpp"

namespace glassmap::localize {

/// One hypothesis.
struct Particle {
  Pose2 pose;          ///< T_map_laser
  double log_w = 0.0;  ///< log weight (normalised so that the weights sum to 1)
};

/// Options of the filter.
struct FilterOptions {
  int max_particles = 2000;              ///< particle count after a global init, and the KLD upper bound
  int min_particles = 100;               ///< KLD lower bound
  bool adaptive = true;                  ///< KLD sampling; false keeps max_particles always
  double kld_epsilon = 0.05;             ///< KLD error bound [-]
  double kld_z = 2.33;                   ///< upper standard-normal quantile of 1 - delta (0.99) [-]
  double kld_bin_xy = 0.25;              ///< KLD histogram bin [m]
  double kld_bin_theta = deg2rad(10.0);  ///< KLD histogram bin [rad]
  double resample_ess = 0.5;             ///< resample when ESS < this fraction of the count [-]
  double alpha_slow = 0.001;             ///< augmented MCL: long-term likelihood average rate [-]
  double alpha_fast = 0.1;               ///< augmented MCL: short-term likelihood average rate [-]
  bool inject = true;                    ///< inject random particles when the likelihood collapses
  /// Recovery only when the map contradicts the estimate: a reading longer than the walls allow
  /// (through a wall, by more than contradiction_gate) cannot come from the right pose, while
  /// clutter, people and unmapped furniture only shorten readings. Injection and re-initialisation
  /// happen only while the smoothed share of such readings at the best particle exceeds
  /// contradiction_share; false: whenever the likelihood drops (plain augmented MCL).
  bool inject_only_when_contradicted = true;
  double contradiction_gate = 0.5;    ///< [m]
  double contradiction_share = 0.15;  ///< [-]
  double contradiction_rate = 0.3;    ///< smoothing of the share per update [-]
  double trust_after_m = 30.0;        ///< after a global localization the gate applies only once the
                                      ///< cloud has stayed converged over this much travel [m]: a cloud
                                      ///< that settled on a look-alike place still needs injection
  double relocalize_ratio = 0.02;     ///< w_fast / w_slow below this: the robot is lost beyond what
                                      ///< injection repairs; restart global localization (0 = never)
  double free_clearance = 0.2;        ///< random particles keep this distance from segments [m]
  double free_reach = 40.0;           ///< ... and lie within this of some segment's box [m]: farther, a
                                      ///< laser sees nothing (bounds memory when a map has strays far away)
  double global_temperature = 30.0;   ///< while the cloud is spread (global localization), the
                                      ///< log-likelihoods are divided by this: annealing that keeps
                                      ///< near-miss hypotheses alive [-]; 1 = off
  double converged_spread = 0.5;      ///< the cloud counts as converged below this std dev [m] ...
  double anneal_min_travel = 5.0;     ///< ... after the robot travelled at least this far [m];
                                      ///< meanwhile KLD keeps at least max_particles / 10
  OdometryNoise noise;                ///< motion model noise
  std::uint64_t seed = 1;             ///< random seed: equal seeds give equal runs
};

/// The particle filter over a sensor model's map.
class ParticleFilter {
 public:
  ParticleFilter(const sensor::SensorModel& model, FilterOptions options);

  /// Particles drawn around `pose` with std devs sigma_xy [m] and sigma_theta [rad].
  void initialize(const Pose2& pose, double sigma_xy = 0.1, double sigma_theta = deg2rad(5.0));
  /// max_particles particles uniform over the free space of the map's bounding box.
  void initializeGlobal();

  /// Moves every particle by the odometry increment (in the laser frame).
  void predict(const OdometryDelta& delta);
  /// Weights by the beams, updates the w_slow/w_fast averages and resamples when the ESS drops.
  /// Returns true when it resampled.
  bool correct(const sensor::BeamSet& beams);

  /// Pose estimate: weighted mean of the particles near the heaviest cluster.
  Pose2 estimate() const;
  /// Weighted std dev of the particle positions around estimate() [m].
  double spread() const;
  /// Effective sample size 1 / sum w^2 [-].
  double effectiveSampleSize() const;
  const std::vector<Particle>& particles() const { return particles_; }
  std::size_t size() const { return particles_.size(); }
  /// True while the log-likelihoods are tempered (after a global init until the cloud converges).
  bool annealing() const { return annealing_; }
  /// Global re-initialisations after a collapse (kidnapping) so far.
  std::size_t relocalizations() const { return relocalizations_; }
  /// Random particles injected at the last resampling.
  std::size_t lastInjected() const { return last_injected_; }
  /// Smoothed share of readings at the best particle that run through a wall [-].
  double contradiction() const { return contradiction_; }
  /// True when recovery (injection, re-initialisation) may act now.
  bool mayRecover() const;
  /// A random pose in free space.
  Pose2 randomFreePose();

 private:
  void resample();
  void collectFreeCells();
  void normalise();

  const sensor::SensorModel& model_;
  FilterOptions opt_;
  std::mt19937_64 rng_;
  std::vector<Particle> particles_;
  /// Public for tests: the centres random particles are drawn around.
 public:
  const std::vector<Vec2>& freeCells() const { return free_cells_; }

 private:
  std::vector<Vec2> free_cells_;  // centres of free cells to draw random particles from
  double free_cell_ = 0.1;        // their size [m]
  double w_slow_ = 0.0, w_fast_ = 0.0;
  std::vector<Pose2> poses_;  // the particles' poses, contiguous, for the model's batch call
  RayCaster walls_;             // the map's walls only: glass may be seen through
  double contradiction_ = 0.0;  // smoothed share of readings through a wall at the best particle
  bool known_start_ = false;    // initialised at a given pose (not globally)
  double converged_at_ = -1.0;  // travelled_ when a global localization's cloud converged, < 0: not yet
  std::size_t last_injected_ = 0;
  bool annealing_ = false;
  std::size_t relocalizations_ = 0;
  double travelled_ = 0.0;  // since the global init [m]
  std::vector<double> scratch_;
};

/// Low-variance (systematic) resampling: indices of `count` draws from normalised `weights`
/// with one random offset u in [0, 1 / count) (Probabilistic Robotics table 4.4).
std::vector<std::size_t> lowVarianceResample(const std::vector<double>& weights, std::size_t count, double u);

/// KLD-sampling bound: particles needed for k occupied bins at error epsilon and quantile z
/// (Fox 2003; Probabilistic Robotics table 8.4, line 15). 0 bins or 1 bin give 1.
std::size_t kldBound(std::size_t bins, double epsilon, double z);

}  // namespace glassmap::localize
