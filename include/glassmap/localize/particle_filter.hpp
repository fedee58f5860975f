#pragma once
/// Monte Carlo localization with several hypotheses: particles over laser poses in the map frame,
/// odometry motion model, a SensorModel, low-variance resampling when the effective sample size
/// drops, KLD-sampling adaptive particle counts (Probabilistic Robotics tables 4.4, 8.2, 8.4).
///
/// The particles are kept in hypotheses (a clustered particle filter, after Milstein et al.,
/// "Robust global localization using clustered particle filtering", AAAI 2002): each is resampled
/// on its own, so a mode with little weight is not wiped out by one lucky scan of another, and each
/// carries its probability (its "mass"), updated by the marginal likelihood of every scan under it
/// (Bayesian model comparison between the places the robot could be). A global localization
/// starts with one broad hypothesis over the free space that splits into modes as the scans
/// concentrate it; the filter is converged when one tight mode holds all but a negligible mass.
///
/// Recovery never replaces a tracked cloud on one bad scan: when the evidence says the robot may
/// be lost (the likelihood drops below its long-run average, or readings run through walls the
/// model cannot explain), a probe (a broad hypothesis of random particles) starts beside the
/// tracked one with a small prior mass, and takes over only if the scans that follow favour it by
/// more than that prior (a sequential likelihood-ratio test); otherwise it dies out, unless it still
/// holds a doubt above converged_doubt (a look-alike place the scans never told apart). A probe
/// is drawn where the scans of the last metres fit (the global start's density of random poses,
/// a quarter of them around the tracked estimate, weighed by those scans), and may not lead while
/// still spread over the floor.
/// A place far from the estimate also needs the scans to say the robot jumped
/// (a break: ScanConsistency) or to have out-explained the estimate over metres: clutter lined up
/// with other walls elsewhere fits for a room, a kidnapped robot's scans contradict its odometry.

#include <cstdint>
#include <optional>
#include <random>
#include <vector>

#include "glassmap/geometry/ray_caster.hpp"
#include "glassmap/localize/motion_model.hpp"
#include "glassmap/localize/scan_consistency.hpp"
#include "glassmap/sensor/sensor_model.hpp"

namespace glassmap::localize {

/// One particle.
struct Particle {
  Pose2 pose;          ///< T_map_laser
  double log_w = 0.0;  ///< log weight (normalised within its hypothesis; particles(): overall)
};

/// One hypothesis: particles around one mode (or, while broad, spread over the free space).
struct Hypothesis {
  std::vector<Particle> particles;  ///< log weights normalised within the hypothesis
  double log_mass = 0.0;            ///< log P(robot in this hypothesis | data), normalised over all [-]
  bool broad = false;               ///< random particles not yet split into modes (annealed)
  bool probe = false;               ///< started as a recovery probe and not yet the best
  double born_m = 0.0;              ///< the filter's travel when it was made [m]
  std::vector<double> last_ll;      ///< each particle's log-likelihood of the last scan (broad ones)
  std::vector<double> log_ratio;    ///< broad ones: each particle's untempered minus annealed log
                                    ///< weight (its mass and its split follow the untempered
                                    ///< posterior; the annealed weights only choose what survives)
  Pose2 estimate;                   ///< weighted mean near its heaviest cell (last correct())
  double spread = 0.0;              ///< weighted RMS distance of its particles from estimate [m]
  double fit = 0.0;                 ///< short-term average of its per-beam marginal likelihood [-]
  double held_m = 0.0;              ///< probes: travel over which it out-explained the tracked estimate
                                    ///< but was kept from leading for want of a break in the scans [m]
  std::uint64_t id = 0;             ///< unique within the filter
};

/// How the filter recovers when the robot may be lost.
enum class Recovery {
  Probe,   ///< a probe hypothesis that must win a likelihood-ratio test (default)
  Inject,  ///< plain augmented MCL: random particles into the cloud whenever the likelihood drops
  None     ///< never
};

/// Options of the filter.
struct FilterOptions {
  int max_particles = 2000;                ///< particles of a hypothesis, and the KLD upper bound
  int min_particles = 500;                 ///< KLD lower bound of the best hypothesis
  int global_particles = 0;                ///< particles of a global initialisation and of the probes
                                           ///< after one (probes from --init: max_particles); 0: from
                                           ///< the free space, global_density per m^2, at least
                                           ///< max_particles and at most max_global_particles
  double global_density = 10.0;            ///< [1/m^2]: one particle per 0.1 m^2 lands within the
                                           ///< reach of a climb (1 m, 20 deg) of any pose
  int max_global_particles = 50000;        ///< [-]
  bool adaptive = true;                    ///< KLD sampling; false keeps max_particles always
  double kld_epsilon = 0.05;               ///< KLD error bound [-]
  double kld_z = 2.33;                     ///< upper standard-normal quantile of 1 - delta (0.99) [-]
  double kld_bin_xy = 0.25;                ///< KLD histogram bin [m]
  double kld_bin_theta = deg2rad(10.0);    ///< KLD histogram bin [rad]
  double resample_ess = 0.5;               ///< resample when ESS < this fraction of the count [-]
  Recovery recovery = Recovery::Probe;     ///< what happens when the robot may be lost
  double alpha_slow = 0.001;               ///< long-term average rate of the per-beam likelihood [-]
  double alpha_fast = 0.1;                 ///< short-term average rate [-]
  double probe_ratio = 0.3;                ///< a probe starts when the short-term likelihood falls under
                                           ///< this fraction of the long-term one ...
  double contradiction_gate = 0.5;         ///< ... or readings run over this far through a wall [m] ...
  double contradiction_share = 0.15;       ///< ... at more than this share of the beams (smoothed) [-],
                                           ///< which clutter never does (it shortens readings)
  double contradiction_rate = 0.3;         ///< smoothing of that share per update [-]
  double probe_prior = 1e-4;               ///< prior probability of "lost" a probe starts with [-]
  double untrusted_probe_prior = 1e-2;     ///< ... after a global localization, until trust_after_m [-]
  double probe_fit = 0.7;                  ///< a probe may lead only once its places explain the scans at
                                           ///< least this well, per beam, against the long-term average of
                                           ///< tracking: where the map explains nothing (clutter, a room
                                           ///< it lacks), a place that explains a little more by chance
                                           ///< is no reason to jump [-]
  double novelty_m = 0.2;                  ///< masses take a scan's evidence in full only after this much
                                           ///< motion (translation + 0.5 m/rad of turning) since the last
                                           ///< update, in proportion below: scans from nearly the same pose
                                           ///< repeat the same clutter and map errors, not new evidence [m]
  ScanConsistencyOptions consistency;      ///< a break in the scans: they contradict the odometry
  double break_memory_m = 2.0;             ///< tracking from a known start (initialize()), a far probe may lead
                                           ///< only while a break is open: from the break until one hypothesis
                                           ///< has led, converged and fitted (probe_fit) over this travel [m] ...
  double doubt_after_m = 4.0;              ///< ... or it out-explained the estimate over this much travel [m]:
                                           ///< a robot in clutter has scans that agree with its odometry,
                                           ///< a kidnapped one has not; a place that lines the clutter up
                                           ///< with other walls fits for a room, not for metres beyond
  double jump_m = 2.0;                     ///< the guard holds only places farther than this from the tracked
  double jump_heading = deg2rad(30.0);     ///< estimate [m], or turned more than this [rad]: nearer ones are a
                                           ///< correction odometry can need (a cloud that slid in clutter)
  bool probe_from_scan = true;             ///< a probe keeps the max_particles (after a global start: as many
                                           ///< as it drew) of a global start's random poses that best fit the
                                           ///< recent scans:
  double probe_history_m = 2.0;            ///< those of the last this much travel since the last break [m],
  int probe_history_scans = 4;             ///< at most this many, evenly spaced (and the current one) [-];
  double probe_near_share = 0.25;          ///< ... (this share of them drawn around the tracked estimate,
                                           ///< jump_m and jump_heading at two sigma, each weighed by uniform /
                                           ///< proposal density) [-]
  int probe_climbs = 256;                  ///< the best this many of them climb on the current scan before
                                           ///< the max_particles are chosen (the probe's mass takes the draws
                                           ///< as drawn: climbed poses are no uniform sample) [-]
  double probe_life_m = 8.0;               ///< a probe that has not won after this travel is dropped [m]
  double probe_cooldown_m = 1.0;           ///< travel between the end of a probe and the next [m]
  double recheck_m = 5.0;                  ///< after a global localization converged, a probe every this
  double trust_after_m = 30.0;             ///< much travel [m] until it stayed converged over this [m]
  double prune_nats = 25.0;                ///< hypotheses this far below the best in log mass are dropped
  int max_hypotheses = 24;                 ///< at most this many hypotheses (the lightest go first)
  int min_hypothesis_particles = 60;       ///< KLD lower bound of the other hypotheses
  double split_after_m = 1.0;              ///< a broad hypothesis splits into modes after this travel [m],
  double split_nats = 15.0;                ///< keeping every mode whose best particle explains the last
                                           ///< scan within this of the best mode's [-]
  double cluster_cell = 1.0;               ///< cells of the mode search [m] ...
  double cluster_heading = deg2rad(30.0);  ///< ... and headings [rad]
  double refine_step = 0.2;                ///< while hypotheses compete, each is moved onto the nearest optimum
  double refine_turn = deg2rad(4.0);       ///< of the scan's likelihood by a pattern search from these
  int refine_levels = 5;                   ///< steps [m, rad], halved this many times (0: no search);
  int refine_broad = 16;                   ///< in a broad hypothesis, its heaviest this many particles climb
  double merge_distance = 0.5;             ///< hypotheses whose estimates are this close merge [m] ...
  double merge_heading = deg2rad(20.0);    ///< ... and this close in heading [rad]
  double converged_doubt = 1e-3;           ///< converged: the other hypotheses hold less mass than this,
  double converged_spread = 0.5;           ///< and the best one's spread is under this [m] ...
  double anneal_min_travel = 5.0;          ///< ... after a global start, the robot travelled this [m]
  double free_clearance = 0.2;             ///< random particles keep this distance from segments [m]
  double free_reach = 40.0;                ///< ... and lie within this of some segment's box [m]: farther, a
                                           ///< laser sees nothing (bounds memory when a map has strays far away)
  double global_temperature = 30.0;        ///< in a broad hypothesis the log-likelihoods of its particles are
                                           ///< divided by this (annealing: near-miss poses stay alive) [-]
  double relocalize_ratio = 0.02;          ///< Recovery::Inject: a collapse under this ratio restarts globally
  OdometryNoise noise;                     ///< motion model noise
  std::uint64_t seed = 1;                  ///< random seed: equal seeds give equal runs
};

/// The particle filter over a sensor model's map.
class ParticleFilter {
 public:
  ParticleFilter(const sensor::SensorModel& model, FilterOptions options);

  /// One hypothesis of max_particles particles drawn around `pose` with std devs sigma_xy [m] and
  /// sigma_theta [rad].
  void initialize(const Pose2& pose, double sigma_xy = 0.1, double sigma_theta = deg2rad(5.0));
  /// One broad hypothesis of globalParticles() particles uniform over the free space.
  void initializeGlobal();
  /// Particles of a global initialisation, and of a probe after one (FilterOptions::global_particles).
  std::size_t globalParticles() const;

  /// Moves every particle by the odometry increment (in the laser frame).
  void predict(const OdometryDelta& delta);
  /// Weights by the beams, updates the hypotheses' masses, splits, merges and prunes them, starts
  /// a probe when the evidence says lost, and resamples each whose ESS dropped. `scan`: the whole
  /// scan for the consistency test against the last one (ScanConsistency; default: `beams`).
  /// Returns true when some hypothesis was resampled.
  bool correct(const sensor::BeamSet& beams, const sensor::BeamSet* scan = nullptr);

  /// Pose estimate: the best hypothesis's weighted mean near its heaviest cell, of the weighted
  /// particles before resampling (resampling only adds noise to the mean).
  Pose2 estimate() const;
  /// RMS distance of the particles of hypotheses holding at least converged_doubt of the mass from
  /// estimate(), mass-weighted [m]: small for one tight mode, large for a spread or split cloud.
  double spread() const;
  /// True when one tight hypothesis holds all but converged_doubt of the mass (see FilterOptions).
  bool converged() const;
  /// Effective sample size 1 / sum w^2 over all particles [-].
  double effectiveSampleSize() const;
  /// Every particle, log weights normalised over all of them (hypothesis mass included).
  std::vector<Particle> particles() const;
  const std::vector<Hypothesis>& hypotheses() const { return hyps_; }
  /// The best hypothesis (highest mass).
  const Hypothesis& best() const;
  std::size_t size() const;
  /// True while a broad hypothesis holds a share of the mass above converged_doubt.
  bool annealing() const;
  /// Times the estimate jumped to another hypothesis (a probe or a rival mode won).
  std::size_t relocalizations() const { return relocalizations_; }
  /// Random particles drawn at the last correct() (a probe, injection or restart).
  std::size_t lastInjected() const { return last_injected_; }
  /// Probes started so far.
  std::size_t probes() const { return probes_; }
  /// Breaks so far: scans that contradicted the one before them placed by odometry.
  std::size_t breaks() const { return breaks_; }
  /// The consistency test of the last correct().
  const ScanConsistencyResult& lastConsistency() const { return consistency_result_; }
  /// Smoothed share of readings at the best particle that run through a wall unexplained [-].
  double contradiction() const { return contradiction_; }  /// A random pose in free space.
  Pose2 randomFreePose();
  /// The motion model's noise, and a new one (self-calibration).
  const OdometryNoise& motionNoise() const { return opt_.noise; }
  void setMotionNoise(const OdometryNoise& noise) { opt_.noise = noise; }
  /// Public for tests: the centres random particles are drawn around.
  const std::vector<Vec2>& freeCells() const { return free_cells_; }

 private:
  void collectFreeCells();
  Hypothesis makeBroad(std::size_t count, double log_mass);
  void weigh(const sensor::BeamSet& beams);
  void updateContradiction(const sensor::BeamSet& beams);
  void maybeStartProbe(const sensor::BeamSet& beams);
  void rememberScan(const sensor::BeamSet& beams);
  // best_place: the probe's mass from the best place it found, not the floor's mean (an untrusted
  // estimate's rechecks).
  Hypothesis probeFromScans(std::size_t count, double log_prior, const sensor::BeamSet& beams, bool best_place = false);
  // Moves a share of a probe's draws near the estimate; returns each draw's log importance weight.
  std::vector<double> drawNearEstimate(Hypothesis& h);
  void organise();  // split, merge, prune, normalise
  bool resample(Hypothesis& h, bool is_best, bool force = false);
  void resetConsistency();
  bool guarded() const;                          // probes must show a break or a long doubt to lead
  bool licensed(const Hypothesis& probe) const;  // ... and this one has
  void refine(Hypothesis& h, const sensor::BeamSet& beams);
  double climb(Pose2& x, const sensor::BeamSet& beams) const;  // local search; returns log p(z | x)
  void injectAugmented(Hypothesis& h, std::size_t count);
  std::size_t bestIndex() const;

  const sensor::SensorModel& model_;
  FilterOptions opt_;
  std::mt19937_64 rng_;
  std::vector<Hypothesis> hyps_;
  std::vector<Vec2> free_cells_;        // centres of free cells to draw random particles from
  double free_cell_ = 0.1;              // their size [m]
  RayCaster walls_;                     // the map's walls only: glass may be seen through
  double w_slow_ = 0.0, w_fast_ = 0.0;  // per-beam likelihood averages of the best hypothesis
  double contradiction_ = 0.0;
  double travelled_ = 0.0;        // since the last initialisation [m]
  double moved_ = 0.0;            // motion since the last correct() (translation + 0.5 m/rad) [m]
  bool global_start_ = false;     // initialised globally (not at a given pose)
  double converged_at_m_ = -1.0;  // travel when a global start first converged; < 0 not yet
  double probe_ended_m_ = -1e9;   // travel when the last probe ended [m]
  double last_recheck_m_ = 0.0;   // travel at the last re-check probe [m]
  std::uint64_t next_id_ = 1;
  std::uint64_t best_id_ = 0;
  Pose2 best_estimate_;
  std::size_t relocalizations_ = 0, last_injected_ = 0, probes_ = 0, breaks_ = 0;
  ScanConsistency consistency_;
  ScanConsistencyResult consistency_result_;
  Pose2 odom_;                    // the odometry integrated without noise (frame of the consistency test)
  bool break_open_ = false;       // a break was seen and the filter has not settled since
  std::uint64_t settled_id_ = 0;  // after a break: the hypothesis settled since settled_m_ (0: none)
  double settled_m_ = 0.0;        // [m]
  double step_m_ = 0.0;           // travel since the correct() before [m]
  double corrected_m_ = 0.0;      // travel at the last correct() [m]
  std::vector<Pose2> poses_;      // all particles' poses, contiguous, for the model's batch call
  std::vector<double> ll_;
  struct RecentScan {
    sensor::BeamSet beams;
    Pose2 odom;            // odom_ when it was taken
    double travelled = 0;  // travelled_ then [m]
    double novelty = 1;    // its novelty and the filter's log marginal likelihood of it
    double marginal = 0;
  };
  std::vector<RecentScan> history_;  // scans a probe is weighed by (rememberScan)
  double last_novelty_ = 1.0;        // novelty of the last scan's evidence [-]
  double last_marginal_ = 0.0;       // log marginal likelihood of the last scan under the filter [-]
};

/// Low-variance (systematic) resampling: indices of `count` draws from normalised `weights`
/// with one random offset u in [0, 1 / count) (Probabilistic Robotics table 4.4).
std::vector<std::size_t> lowVarianceResample(const std::vector<double>& weights, std::size_t count, double u);

/// KLD-sampling bound: particles needed for k occupied bins at error epsilon and quantile z
/// (Fox 2003; Probabilistic Robotics table 8.4, line 15). 0 bins or 1 bin give 1.
std::size_t kldBound(std::size_t bins, double epsilon, double z);

}  // namespace glassmap::localize
