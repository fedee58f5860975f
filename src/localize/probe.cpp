// Recovery probes (and a global start's rechecks): drawn where the recent scans fit.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <random>

#include "glassmap/localize/particle_filter.hpp"
#include "hypotheses.hpp"

namespace glassmap::localize {

void ParticleFilter::rememberScan(const sensor::BeamSet& beams) {
  // The scans since the last break (the odometry between them holds), one per
  // probe_history_m / probe_history_scans of travel, over the last probe_history_m.
  if (opt_.recovery != Recovery::Probe || !opt_.probe_from_scan || opt_.probe_history_scans <= 0) return;
  const double spacing = opt_.probe_history_m / opt_.probe_history_scans;
  if (!history_.empty() && travelled_ - history_.back().travelled < spacing) return;
  history_.push_back({beams, odom_, travelled_, last_novelty_, last_marginal_});
  while (!history_.empty() && travelled_ - history_.front().travelled > opt_.probe_history_m)
    history_.erase(history_.begin());
}

std::vector<double> ParticleFilter::drawNearEstimate(Hypothesis& h) {
  const std::size_t n = h.particles.size();
  std::vector<double> log_iw(n, 0.0);
  const double share = std::clamp(opt_.probe_near_share, 0.0, 1.0);
  const auto local = static_cast<std::size_t>(std::floor(share * static_cast<double>(n)));
  if (local == 0 || hyps_.empty()) return log_iw;
  const Pose2 at = best().estimate;
  const double sxy = 0.5 * opt_.jump_m, sth = 0.5 * opt_.jump_heading;
  std::normal_distribution<double> n01(0.0, 1.0);
  for (std::size_t i = n - local; i < n; ++i)
    h.particles[i].pose = Pose2(at.t + sxy * Vec2(n01(rng_), n01(rng_)), wrapAngle(at.theta + sth * n01(rng_)));
  // Density of the uniform draws over the free space and headings, and of the local ones.
  double area = static_cast<double>(free_cells_.size()) * free_cell_ * free_cell_;
  if (!(area > 0)) area = std::max(model_.map().bounds().volume(), 1.0);
  const double log_uniform = -std::log(area * 2.0 * kPi);
  const double log_norm = -std::log(2.0 * kPi * sxy * sxy) - std::log(std::sqrt(2.0 * kPi) * sth);
  for (std::size_t i = 0; i < n; ++i) {
    const Pose2& x = h.particles[i].pose;
    const double d2 = (x.t - at.t).squaredNorm() / (sxy * sxy);
    const double a = angleDiff(x.theta, at.theta) / sth;
    const double log_local = log_norm - 0.5 * (d2 + a * a);
    // uniform / ((1 - share) uniform + share local)
    const std::array<double, 2> terms{std::log1p(-share), std::log(share) + log_local - log_uniform};
    log_iw[i] = -detail::logSumExp(terms);
  }
  return log_iw;
}

Hypothesis ParticleFilter::probeFromScans(std::size_t count, double log_prior, const sensor::BeamSet& beams,
                                          bool best_place) {
  // The probe is the broad hypothesis "the robot is anywhere on the floor" as it would stand had it
  // started at the oldest remembered scan: as many random poses as a global start draws, each
  // weighed by the remembered scans (placed back along the odometry) and the current one, and
  // `count` of them kept by their annealed weights (the untempered rest carried in log_ratio, as a
  // broad hypothesis does). Its mass takes those scans too. A probe of `count` uniform draws weighed by
  // nothing holds the robot's place only by luck (500 over a 450 m^2 floor: one in three near it),
  // and one scan along a corridor fits every place along it.
  const std::size_t n = std::max(globalParticles(), count);
  Hypothesis h = makeBroad(n, log_prior);
  // A share of the draws lands near the tracked estimate (within the reach of a correction the
  // odometry could have needed: jump_m, jump_heading at two sigma): a cloud that slid off along a
  // corridor or into a part of the floor the plan leaves empty is most often a metre or two from the
  // robot, where uniform draws are one per third of a square metre at any heading. Each draw is
  // weighed by uniform / proposal density, so the probe still stands for "anywhere on the floor".
  const std::vector<double> log_iw = drawNearEstimate(h);
  std::vector<Pose2> at(n);
  std::vector<double> score(n, 0.0), current(n), ll(n);
  double filter_marginal = 0.0;
  const auto weighAll = [&](const sensor::BeamSet& b, std::vector<double>& out) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 64), [&](const tbb::blocked_range<std::size_t>& r) {
      model_.logLikelihoods(std::span<const Pose2>(at).subspan(r.begin(), r.size()), b, &out[r.begin()]);
    });
  };
  // Each remembered scan's laser pose in the current one's frame.
  std::vector<Pose2> backs;
  for (const RecentScan& s : history_) backs.push_back(odom_.inverse() * s.odom);
  for (std::size_t m = 0; m < history_.size(); ++m) {
    const RecentScan& s = history_[m];
    for (std::size_t i = 0; i < n; ++i) at[i] = h.particles[i].pose * backs[m];
    weighAll(s.beams, ll);
    for (std::size_t i = 0; i < n; ++i) score[i] += s.novelty * ll[i];
    filter_marginal += s.novelty * s.marginal;
  }
  for (std::size_t i = 0; i < n; ++i) at[i] = h.particles[i].pose;
  weighAll(beams, current);
  for (std::size_t i = 0; i < n; ++i) score[i] += last_novelty_ * current[i];
  filter_marginal += last_novelty_ * last_marginal_;
  // The mass: the scans' marginal likelihood over the floor (the mean over uniform draws) against
  // that over the filter's hypotheses.
  std::vector<double> weighted(n);
  for (std::size_t i = 0; i < n; ++i) weighted[i] = score[i] + log_iw[i];
  h.log_mass = log_prior + detail::logSumExp(weighted) - std::log(static_cast<double>(n)) - filter_marginal;
  // The best of them climb to the nearest optimum of the current scan's likelihood and are weighed
  // again (their place in the cloud, not the mass: a climbed pose is no uniform draw): a random
  // pose rarely lands within centimetres of the robot, often within a climb's reach.
  const std::size_t k = std::min<std::size_t>(n, static_cast<std::size_t>(std::max(opt_.probe_climbs, 0)));
  if (k > 0) {
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(k), order.end(),
                      [&](std::size_t a, std::size_t b) { return score[a] > score[b]; });
    order.resize(k);
    std::vector<Pose2> climbed(k);
    std::vector<double> cur(k), sc(k);
    tbb::parallel_for(std::size_t{0}, k, [&](std::size_t j) {
      Pose2 x = h.particles[order[j]].pose;
      cur[j] = climb(x, beams);
      double s = last_novelty_ * cur[j];
      for (std::size_t m = 0; m < history_.size(); ++m)
        s += history_[m].novelty * model_.logLikelihood(x * backs[m], history_[m].beams);
      climbed[j] = x;
      sc[j] = s;
    });
    for (std::size_t j = 0; j < k; ++j)
      if (sc[j] > score[order[j]]) {
        h.particles[order[j]].pose = climbed[j];
        score[order[j]] = sc[j];
        current[order[j]] = cur[j];
      }
  }
  if (best_place) {
    // An estimate not yet trusted (a global start's) was itself chosen from the whole floor: its
    // mass paid for the floor's size at the start. A recheck weighed by the floor's mean pays it
    // again, and a look-alike place that explains the scans as well as the estimate (or somewhat
    // better) never becomes a rival (no-glass, seed 3: converged 28 m off on the mirror image).
    // Its mass is that of the best place it found: the recent scans' likelihood there against the
    // filter's, times the prior.
    h.log_mass = log_prior + *std::max_element(score.begin(), score.end()) - filter_marginal;
  }
  const double inv_t = 1.0 / std::max(opt_.global_temperature, 1.0);
  std::vector<double> w(n);
  for (std::size_t i = 0; i < n; ++i) w[i] = inv_t * score[i] + log_iw[i];
  const double norm = detail::logSumExp(w);
  for (double& v : w) v = std::exp(v - norm);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const std::vector<std::size_t> kept = lowVarianceResample(w, count, u01(rng_) / static_cast<double>(count));
  std::vector<Particle> particles;
  particles.reserve(count);
  h.log_ratio.clear();
  h.last_ll.clear();
  const double log_w = -std::log(static_cast<double>(count));
  for (std::size_t i : kept) {
    particles.push_back({h.particles[i].pose, log_w});
    h.log_ratio.push_back((1.0 - inv_t) * score[i]);
    h.last_ll.push_back(current[i]);
  }
  h.particles = std::move(particles);
  detail::summarise(h);
  return h;
}

}  // namespace glassmap::localize
