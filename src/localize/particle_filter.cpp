#include "glassmap/localize/particle_filter.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "glassmap/core/error.hpp"
#include "glassmap/core/split_mix.hpp"
#include "hypotheses.hpp"

namespace glassmap::localize {
namespace {

// Particles per block of the motion step (each block one random stream).
constexpr std::size_t kMotionBlock = 256;

VectorMap wallsOf(const VectorMap& map) {
  VectorMap walls;
  for (const MapSegment& s : map.segments)
    if (s.material == Material::Wall) walls.segments.push_back(s);
  return walls;
}

}  // namespace

std::vector<std::size_t> lowVarianceResample(const std::vector<double>& weights, std::size_t count, double u) {
  std::vector<std::size_t> out;
  out.reserve(count);
  if (weights.empty() || count == 0) return out;
  const double step = 1.0 / static_cast<double>(count);
  double c = weights[0];
  std::size_t i = 0;
  for (std::size_t m = 0; m < count; ++m) {
    const double target = u + static_cast<double>(m) * step;
    while (target > c && i + 1 < weights.size()) c += weights[++i];
    out.push_back(i);
  }
  return out;
}

std::size_t kldBound(std::size_t bins, double epsilon, double z) {
  if (bins <= 1) return 1;
  const double k = static_cast<double>(bins - 1);
  const double a = 2.0 / (9.0 * k);
  const double b = 1.0 - a + std::sqrt(a) * z;
  return static_cast<std::size_t>(std::ceil(k / (2.0 * epsilon) * b * b * b));
}

ParticleFilter::ParticleFilter(const sensor::SensorModel& model, FilterOptions options)
    : model_(model),
      opt_(options),
      rng_(options.seed),
      walls_(wallsOf(model.map())),
      consistency_(options.consistency) {
  if (opt_.max_particles < 1) throw Error("the particle count must be positive", {}, 0, "particles");
  opt_.min_particles = std::clamp(opt_.min_particles, 1, opt_.max_particles);
  opt_.min_hypothesis_particles = std::clamp(opt_.min_hypothesis_particles, 1, opt_.min_particles);
  if (opt_.global_particles < 0) throw Error("the global particle count must not be negative", {}, 0, "particles");
  collectFreeCells();
}

std::size_t ParticleFilter::globalParticles() const {
  if (opt_.global_particles > 0) return static_cast<std::size_t>(opt_.global_particles);
  const double area = static_cast<double>(free_cells_.size()) * free_cell_ * free_cell_;
  const double n = std::clamp(area * opt_.global_density, static_cast<double>(opt_.max_particles),
                              static_cast<double>(std::max(opt_.max_global_particles, opt_.max_particles)));
  return static_cast<std::size_t>(n);
}

Hypothesis ParticleFilter::makeBroad(std::size_t count, double log_mass) {
  Hypothesis h;
  h.broad = true;
  h.log_mass = log_mass;
  h.born_m = travelled_;
  h.id = next_id_++;
  h.particles.resize(count);
  const double log_w = -std::log(static_cast<double>(count));
  for (Particle& p : h.particles) {
    p.pose = randomFreePose();
    p.log_w = log_w;
  }
  detail::summarise(h);
  return h;
}

void ParticleFilter::initialize(const Pose2& pose, double sigma_xy, double sigma_theta) {
  std::normal_distribution<double> n01(0.0, 1.0);
  Hypothesis h;
  h.id = next_id_++;
  h.particles.resize(static_cast<std::size_t>(opt_.max_particles));
  const double log_w = -std::log(static_cast<double>(h.particles.size()));
  for (Particle& p : h.particles) {
    p.pose = Pose2(pose.t + sigma_xy * Vec2(n01(rng_), n01(rng_)), pose.theta + sigma_theta * n01(rng_));
    p.log_w = log_w;
  }
  detail::summarise(h);
  hyps_.clear();
  hyps_.push_back(std::move(h));
  w_slow_ = w_fast_ = 0.0;
  contradiction_ = 0.0;
  travelled_ = 0.0;
  resetConsistency();
  global_start_ = false;
  converged_at_m_ = -1.0;
  probe_ended_m_ = -1e9;
  best_id_ = hyps_.front().id;
  best_estimate_ = hyps_.front().estimate;
}

void ParticleFilter::initializeGlobal() {
  travelled_ = 0.0;
  const auto count = globalParticles();
  hyps_.clear();
  hyps_.push_back(makeBroad(count, 0.0));
  w_slow_ = w_fast_ = 0.0;
  contradiction_ = 0.0;
  resetConsistency();
  global_start_ = true;
  converged_at_m_ = -1.0;
  probe_ended_m_ = -1e9;
  last_recheck_m_ = 0.0;
  best_id_ = hyps_.front().id;
  best_estimate_ = hyps_.front().estimate;
}

void ParticleFilter::predict(const OdometryDelta& delta) {
  travelled_ += std::abs(delta.trans);
  moved_ += std::abs(delta.trans) + 0.5 * (std::abs(delta.rot1) + std::abs(delta.rot2));
  const Pose2 step(delta.trans * Vec2(std::cos(delta.rot1), std::sin(delta.rot1)), delta.rot1 + delta.rot2);
  odom_ = odom_ * step;
  // Each block of particles draws from its own stream, seeded from the filter's generator, the
  // hypothesis and the block: the blocks run in parallel and the result does not depend on the
  // thread count.
  const MotionSpread spread = motionSpread(delta, opt_.noise);
  const std::uint64_t step_seed = rng_();
  for (std::size_t hi = 0; hi < hyps_.size(); ++hi) {
    Hypothesis& h = hyps_[hi];
    const std::size_t n = h.particles.size();
    const std::size_t blocks = (n + kMotionBlock - 1) / kMotionBlock;
    tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
      SplitMix gen(splitMix64(step_seed ^ splitMix64(hi << 32 | b)));
      const std::size_t end = std::min(n, (b + 1) * kMotionBlock);
      for (std::size_t i = b * kMotionBlock; i < end; ++i) {
        const double n_rot1 = gen.normal(), n_trans = gen.normal();
        h.particles[i].pose = applyMotion(h.particles[i].pose, delta, spread, n_rot1, n_trans, gen.normal());
      }
    });
    h.estimate = h.estimate * step;
  }
}

Pose2 ParticleFilter::estimate() const { return hyps_.empty() ? Pose2() : best().estimate; }

void ParticleFilter::weigh(const sensor::BeamSet& beams) {
  std::size_t n = 0;
  for (const Hypothesis& h : hyps_) n += h.particles.size();
  poses_.resize(n);
  ll_.resize(n);
  std::size_t k = 0;
  for (const Hypothesis& h : hyps_)
    for (const Particle& p : h.particles) poses_[k++] = p.pose;
  // Weighting is the only parallel step: each particle's likelihood is a pure function of its
  // pose, so results do not depend on the thread count. Chunks of 129-256 particles: the models'
  // batch calls cast one beam of a chunk as one coherent group (smaller chunks pay a grid sweep per
  // few dozen rays; 2,500 particles still make 16 chunks for the threads to share).
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 256), [&](const tbb::blocked_range<std::size_t>& r) {
    model_.logLikelihoods(std::span<const Pose2>(poses_).subspan(r.begin(), r.size()), beams, &ll_[r.begin()]);
  });
  // Each hypothesis: its mass times the scan's marginal likelihood under it (the mean likelihood of
  // its weighted particles), in proportion to how new the view is; its particles' weights, annealed
  // while it is broad.
  const double novelty = opt_.novelty_m > 0 ? std::min(1.0, moved_ / opt_.novelty_m) : 1.0;
  moved_ = 0.0;
  const double nb = static_cast<double>(beams.size());
  std::vector<double> total, tmp;
  k = 0;
  for (Hypothesis& h : hyps_) {
    // A broad hypothesis is annealed, and takes a scan in proportion to how new its view is: ten
    // scans from where the robot stood still would otherwise undo the annealing.
    const double inv_t = h.broad ? novelty / std::max(opt_.global_temperature, 1.0) : 1.0;
    tmp.resize(h.particles.size());
    double marginal = 0.0;
    if (h.broad) {
      // The untempered weights: annealed ones times the ratio carried along.
      h.log_ratio.resize(h.particles.size(), 0.0);
      for (std::size_t i = 0; i < h.particles.size(); ++i) tmp[i] = h.particles[i].log_w + h.log_ratio[i];
      const double base = detail::logSumExp(tmp);
      for (std::size_t i = 0; i < h.particles.size(); ++i) tmp[i] += ll_[k + i];
      marginal = detail::logSumExp(tmp) - base;
      for (std::size_t i = 0; i < h.particles.size(); ++i) h.log_ratio[i] += (1.0 - inv_t) * ll_[k + i];
    } else {
      for (std::size_t i = 0; i < h.particles.size(); ++i) tmp[i] = h.particles[i].log_w + ll_[k + i];
      marginal = detail::logSumExp(tmp);
    }
    for (std::size_t i = 0; i < h.particles.size(); ++i) tmp[i] = h.particles[i].log_w += inv_t * ll_[k + i];
    if (h.broad)
      h.last_ll.assign(ll_.begin() + static_cast<std::ptrdiff_t>(k),
                       ll_.begin() + static_cast<std::ptrdiff_t>(k + h.particles.size()));
    const double norm = detail::logSumExp(tmp);
    for (Particle& p : h.particles) p.log_w -= norm;
    total.push_back(h.log_mass + marginal);
    h.log_mass += novelty * marginal;
    const double per_beam = std::exp(marginal / nb);
    h.fit = h.fit > 0 ? h.fit + opt_.alpha_fast * 3.0 * (per_beam - h.fit) : per_beam;
    k += h.particles.size();
    detail::summarise(h);
  }
  // The filter's marginal likelihood per beam (a geometric mean keeps it in range for any beam
  // count): its short- and long-term averages tell a sudden drop (table 8.3).
  last_novelty_ = novelty;
  last_marginal_ = detail::logSumExp(total);
  const double w_avg = std::exp(last_marginal_ / nb);
  if (w_slow_ <= 0.0 || !std::isfinite(w_slow_)) {
    w_slow_ = w_fast_ = w_avg;
  } else {
    w_slow_ += opt_.alpha_slow * (w_avg - w_slow_);
    w_fast_ += opt_.alpha_fast * (w_avg - w_fast_);
  }
}

void ParticleFilter::updateContradiction(const sensor::BeamSet& beams) {
  // Readings through a wall at the best particle of the best hypothesis that the model leaves to
  // its random-reading floor: what no clutter can explain (clutter shortens readings; a reflection
  // off a pane runs "through" the wall behind it, but the glass model explains it).
  const Hypothesis& h = best();
  if (h.broad || h.particles.empty()) return;
  const auto top = std::max_element(h.particles.begin(), h.particles.end(),
                                    [](const Particle& a, const Particle& b) { return a.log_w < b.log_w; });
  const Eigen::Matrix2d R = top->pose.rotation();
  const sensor::SensorParams& mp = model_.params();
  const double w_rand = mp.z_rand / (mp.z_hit + mp.z_short + mp.z_max + mp.z_rand);
  const double log_unexplained = std::log(2.0 * w_rand / beams.max_range);
  std::size_t valid = 0, through = 0;
  for (std::size_t i = 0; i < beams.size(); ++i) {
    const double z = beams.ranges[i];
    if (!(z < beams.max_range)) continue;
    ++valid;
    const Vec2 dir = R * beams.dirs[i];
    const double e = walls_.castRange(top->pose.t, dir, beams.max_range);
    through +=
        z > e + opt_.contradiction_gate && model_.logLikelihood(top->pose, dir, z, beams.max_range) < log_unexplained;
  }
  if (valid > 0) {
    const double share = static_cast<double>(through) / static_cast<double>(valid);
    contradiction_ += opt_.contradiction_rate * (share - contradiction_);
  }
}

void ParticleFilter::maybeStartProbe(const sensor::BeamSet& beams) {
  if (opt_.recovery != Recovery::Probe || hyps_.empty()) return;
  for (const Hypothesis& h : hyps_)
    if (h.broad) return;
  const bool lost = (w_slow_ > 0 && w_fast_ < opt_.probe_ratio * w_slow_) || contradiction_ > opt_.contradiction_share;
  // After a global localization converged, a look-alike place may have won: look again now and
  // then until the estimate has stayed converged over trust_after_m.
  const bool recheck = global_start_ && converged_at_m_ >= 0 && travelled_ - converged_at_m_ < opt_.trust_after_m &&
                       travelled_ - last_recheck_m_ >= opt_.recheck_m;
  if (!recheck && !(lost && travelled_ - probe_ended_m_ >= opt_.probe_cooldown_m)) return;
  // After a global localization that has not yet stayed converged over trust_after_m, "elsewhere"
  // is far more likely than for a robot tracked from a known start.
  const bool trusted = !global_start_ || (converged_at_m_ >= 0 && travelled_ - converged_at_m_ >= opt_.trust_after_m);
  const double prior = trusted ? opt_.probe_prior : opt_.untrusted_probe_prior;
  const double keep = std::log1p(-prior);
  for (Hypothesis& h : hyps_) h.log_mass += keep;
  // After a global start the likely error is a look-alike place: the probe searches the floor as
  // densely as the global localization did. From a given start (--init) it is a check against a
  // kidnapping, of max_particles: more random particles only find more places that fit the
  // clutter of a real scan (Freiburg 079 with perfect odometry: lost with a probe from the free
  // area, 0.05 m with max_particles).
  const auto count = global_start_ ? globalParticles() : static_cast<std::size_t>(opt_.max_particles);
  Hypothesis probe = !opt_.probe_from_scan ? makeBroad(count, std::log(prior))
                                           : probeFromScans(count, std::log(prior), beams, !trusted);
  probe.probe = true;
  // Still broad, it may not lead a tracked estimate, not even on the scan it starts with (its
  // mass took the recent scans, the estimate's came from further back).
  if (guarded()) {
    double lead = -std::numeric_limits<double>::infinity();
    for (const Hypothesis& h : hyps_) lead = std::max(lead, h.log_mass);
    probe.log_mass = std::min(probe.log_mass, lead - 1.0);
  }
  hyps_.push_back(std::move(probe));
  ++probes_;
  last_injected_ = count;
  if (recheck) last_recheck_m_ = travelled_;
  w_fast_ = w_slow_;  // the drop has been acted on
}

void ParticleFilter::injectAugmented(Hypothesis& h, std::size_t count) {
  // Plain augmented MCL: the last `count` particles of the resampled set become random ones.
  count = std::min(count, h.particles.size());
  for (std::size_t k = h.particles.size() - count; k < h.particles.size(); ++k) h.particles[k].pose = randomFreePose();
  last_injected_ = count;
  if (count > 0) w_fast_ = w_slow_;  // the averages restart, so one bad scan does not keep scattering
}

void ParticleFilter::resetConsistency() {
  consistency_.reset();
  consistency_result_ = {};
  odom_ = Pose2();
  break_open_ = false;
  history_.clear();
  corrected_m_ = travelled_;
}

bool ParticleFilter::guarded() const {
  // A robot tracked from a known start is lost by a kidnapping (or an odometry jump), which its
  // scans show as a break. After a global start the likely error is a look-alike place, which no
  // break tells; the rechecks and probes there are as before.
  return opt_.recovery == Recovery::Probe && !global_start_;
}

bool ParticleFilter::licensed(const Hypothesis& probe) const {
  return break_open_ || probe.held_m >= opt_.doubt_after_m;
}

bool ParticleFilter::correct(const sensor::BeamSet& beams, const sensor::BeamSet* scan) {
  last_injected_ = 0;
  if (hyps_.empty() || beams.size() == 0) return false;
  step_m_ = travelled_ - corrected_m_;
  corrected_m_ = travelled_;
  weigh(beams);
  // The scans against each other: a break says the robot (or its odometry) jumped.
  consistency_result_ = consistency_.add(scan ? *scan : beams, odom_);
  if (consistency_result_.broke) {
    break_open_ = true;
    history_.clear();  // the scans before it were taken elsewhere
    settled_id_ = 0;   // settled_m_ restarts at the next lead (below)
    ++breaks_;
  }
  updateContradiction(beams);
  organise();
  if (hyps_.empty()) return false;

  // The places a probe or a global localization proposes are moved onto their nearest optimum of
  // the scan's likelihood: a random particle near the robot rarely lands within a few centimetres
  // of it. A tracked cloud is left to its motion model (one scan's optimum overfits its clutter).
  for (Hypothesis& h : hyps_)
    if (h.probe || (global_start_ && converged_at_m_ < 0)) refine(h, beams);
  bool resampled = false;
  if (opt_.recovery == Recovery::Inject && !annealing()) {
    // A collapse of the likelihood to a fiftieth of its average restarts globally; milder drops
    // inject random particles in proportion.
    if (opt_.relocalize_ratio > 0 && w_fast_ < opt_.relocalize_ratio * w_slow_) {
      const bool was_global = global_start_;
      initializeGlobal();
      global_start_ = was_global;
      ++relocalizations_;
      last_injected_ = size();
      return true;
    }
    const double p_inject = w_slow_ > 0 ? std::max(0.0, 1.0 - w_fast_ / w_slow_) : 0.0;
    Hypothesis& h = hyps_[bestIndex()];
    if (p_inject > 0.05) {
      // Resample the best hypothesis, then replace a share by random particles.
      resampled = resample(h, true, true);
      injectAugmented(h, static_cast<std::size_t>(std::floor(p_inject * static_cast<double>(h.particles.size()))));
    }
  }
  const std::size_t b = bestIndex();
  for (std::size_t i = 0; i < hyps_.size(); ++i) resampled = resample(hyps_[i], i == b) || resampled;

  // Which hypothesis leads: a jump to another place counts as a relocalization.
  Hypothesis& lead = hyps_[b];
  if (lead.id != best_id_) {
    if ((lead.estimate.t - best_estimate_.t).norm() > opt_.merge_distance) ++relocalizations_;
    best_id_ = lead.id;
  }
  lead.probe = false;  // a probe that leads has won
  best_estimate_ = lead.estimate;
  // A break keeps recovery open until the filter has settled again: one hypothesis has led,
  // converged and explained the scans as well as tracking usually does, over break_memory_m of
  // travel (a look-alike place along a corridor fits for a moment, not for metres). The tracked
  // estimate of a robot that did not jump passes after break_memory_m; a kidnapped robot's
  // recovery stays open however long its true place takes to be found.
  if (break_open_) {
    const bool settled = converged() && lead.fit >= opt_.probe_fit * w_slow_;
    if (!settled || lead.id != settled_id_) {
      settled_id_ = settled ? lead.id : 0;
      settled_m_ = travelled_;
    } else if (travelled_ - settled_m_ >= opt_.break_memory_m) {
      break_open_ = false;
    }
  }
  if (global_start_ && converged_at_m_ < 0 && converged()) {
    converged_at_m_ = travelled_;
    last_recheck_m_ = travelled_;
  }
  maybeStartProbe(beams);
  rememberScan(beams);
  return resampled;
}

}  // namespace glassmap::localize
