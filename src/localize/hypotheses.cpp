// The hypotheses of the particle filter: summaries, modes, split / merge / prune, resampling.
#include "hypotheses.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <unordered_map>
#include <unordered_set>

namespace glassmap::localize {
namespace detail {

double logSumExp(std::span<const double> v) {
  double m = -std::numeric_limits<double>::infinity();
  for (double x : v) m = std::max(m, x);
  if (!std::isfinite(m)) return m;
  double s = 0.0;
  for (double x : v) s += std::exp(x - m);
  return m + std::log(s);
}

std::int64_t binKey(const Pose2& p, double bin_xy, double bin_theta) {
  const auto ix = static_cast<std::int64_t>(std::floor(p.x() / bin_xy));
  const auto iy = static_cast<std::int64_t>(std::floor(p.y() / bin_xy));
  const auto it = static_cast<std::int64_t>(std::floor((p.theta + kPi) / bin_theta));
  return ((ix & 0xFFFFF) << 40) | ((iy & 0xFFFFF) << 20) | (it & 0xFFFFF);
}

void summarise(Hypothesis& h) {
  h.estimate = Pose2();
  h.spread = 0.0;
  if (h.particles.empty()) return;
  // Heaviest 1 m cell, then the weighted mean of the particles within 1 m of its mean.
  struct Acc {
    double w = 0;
    Vec2 s = Vec2::Zero();
  };
  std::unordered_map<std::int64_t, Acc> cells;
  for (const Particle& p : h.particles) {
    Acc& a = cells[binKey(Pose2(p.pose.t, 0.0), 1.0, 2.0 * kPi + 1.0)];
    const double w = std::exp(p.log_w);
    a.w += w;
    a.s += w * p.pose.t;
  }
  const Acc* best = nullptr;
  std::int64_t best_key = 0;
  for (const auto& [key, a] : cells)
    if (!best || a.w > best->w || (a.w == best->w && key < best_key)) {
      best = &a;
      best_key = key;
    }
  const Vec2 centre = best->w > 0 ? Vec2(best->s / best->w) : h.particles.front().pose.t;
  double wsum = 0, c = 0, s = 0;
  Vec2 t = Vec2::Zero();
  for (const Particle& p : h.particles) {
    if ((p.pose.t - centre).norm() > 1.0) continue;
    const double w = std::exp(p.log_w);
    wsum += w;
    t += w * p.pose.t;
    c += w * std::cos(p.pose.theta);
    s += w * std::sin(p.pose.theta);
  }
  h.estimate = wsum > 0 ? Pose2(t / wsum, std::atan2(s, c)) : h.particles.front().pose;
  double sq = 0, all = 0;
  for (const Particle& p : h.particles) {
    const double w = std::exp(p.log_w);
    sq += w * (p.pose.t - h.estimate.t).squaredNorm();
    all += w;
  }
  h.spread = all > 0 ? std::sqrt(sq / all) : 0.0;
}

std::vector<Mode> modesOf(const Hypothesis& h, double cell, double heading_bin) {
  // Occupied cells, then union-find over neighbouring ones.
  const int n_heading = std::max(1, static_cast<int>(std::round(2.0 * kPi / heading_bin)));
  const double hb = 2.0 * kPi / n_heading;
  struct Cell {
    std::int64_t ix, iy;
    int it;
  };
  auto key = [](std::int64_t ix, std::int64_t iy, int it) {
    return ((ix & 0xFFFFFF) << 36) | ((iy & 0xFFFFFF) << 12) | (static_cast<std::int64_t>(it) & 0xFFF);
  };
  std::unordered_map<std::int64_t, std::size_t> index;
  std::vector<Cell> cells;
  std::vector<std::size_t> cell_of(h.particles.size());
  for (std::size_t i = 0; i < h.particles.size(); ++i) {
    const Pose2& p = h.particles[i].pose;
    const auto ix = static_cast<std::int64_t>(std::floor(p.x() / cell));
    const auto iy = static_cast<std::int64_t>(std::floor(p.y() / cell));
    const int it = std::clamp(static_cast<int>(std::floor((wrapAngle(p.theta) + kPi) / hb)), 0, n_heading - 1);
    const auto [at, fresh] = index.try_emplace(key(ix, iy, it), cells.size());
    if (fresh) cells.push_back({ix, iy, it});
    cell_of[i] = at->second;
  }
  // Cells lighter than a twentieth of the mean are stragglers: they join no mode.
  std::vector<double> cell_weight(cells.size(), 0.0);
  double total = 0.0;
  for (std::size_t i = 0; i < h.particles.size(); ++i) {
    const double w = std::exp(h.particles[i].log_w);
    cell_weight[cell_of[i]] += w;
    total += w;
  }
  const double light = 0.05 * total / static_cast<double>(std::max<std::size_t>(cells.size(), 1));
  std::vector<std::size_t> parent(cells.size());
  std::iota(parent.begin(), parent.end(), std::size_t{0});
  auto find = [&](std::size_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  for (std::size_t c = 0; c < cells.size(); ++c)
    if (cell_weight[c] >= light)
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dt = -1; dt <= 1; ++dt) {
            const int it = ((cells[c].it + dt) % n_heading + n_heading) % n_heading;
            const auto f = index.find(key(cells[c].ix + dx, cells[c].iy + dy, it));
            if (f == index.end() || cell_weight[f->second] < light) continue;
            const std::size_t a = find(c), b = find(f->second);
            if (a != b) parent[std::max(a, b)] = std::min(a, b);
          }
  std::unordered_map<std::size_t, std::size_t> group;
  std::vector<Mode> modes;
  for (std::size_t i = 0; i < h.particles.size(); ++i) {
    if (cell_weight[cell_of[i]] < light) continue;
    const auto [at, fresh] = group.try_emplace(find(cell_of[i]), modes.size());
    if (fresh) modes.emplace_back();
    modes[at->second].members.push_back(i);
    modes[at->second].weight += std::exp(h.particles[i].log_w);
  }
  std::stable_sort(modes.begin(), modes.end(), [](const Mode& a, const Mode& b) { return a.weight > b.weight; });
  return modes;
}

}  // namespace detail

std::size_t ParticleFilter::bestIndex() const {
  std::size_t b = 0;
  for (std::size_t i = 1; i < hyps_.size(); ++i)
    if (hyps_[i].log_mass > hyps_[b].log_mass) b = i;
  return b;
}

const Hypothesis& ParticleFilter::best() const { return hyps_[bestIndex()]; }

std::size_t ParticleFilter::size() const {
  std::size_t n = 0;
  for (const Hypothesis& h : hyps_) n += h.particles.size();
  return n;
}

std::vector<Particle> ParticleFilter::particles() const {
  std::vector<Particle> out;
  out.reserve(size());
  for (const Hypothesis& h : hyps_)
    for (const Particle& p : h.particles) out.push_back({p.pose, p.log_w + h.log_mass});
  return out;
}

double ParticleFilter::effectiveSampleSize() const {
  double s = 0.0;
  for (const Hypothesis& h : hyps_)
    for (const Particle& p : h.particles) s += std::exp(2.0 * (p.log_w + h.log_mass));
  return s > 0 ? 1.0 / s : 0.0;
}

bool ParticleFilter::annealing() const {
  for (const Hypothesis& h : hyps_)
    if (h.broad && std::exp(h.log_mass) > opt_.converged_doubt) return true;
  return false;
}

bool ParticleFilter::converged() const {
  if (hyps_.empty()) return false;
  const Hypothesis& b = best();
  if (b.broad || b.spread >= opt_.converged_spread) return false;
  // The rival places hold the doubt; a probe still spread over the floor is a search, not a rival
  // (after a global start, the one broad hypothesis that is not a probe is the search itself).
  double rivals = 0.0;
  for (const Hypothesis& h : hyps_)
    if (&h != &b && (!h.broad || !h.probe)) rivals += std::exp(h.log_mass - b.log_mass);
  if (rivals >= opt_.converged_doubt) return false;
  return !global_start_ || travelled_ >= opt_.anneal_min_travel;
}

double ParticleFilter::spread() const {
  if (hyps_.empty()) return 0.0;
  const Pose2 e = estimate();
  double s = 0, wsum = 0;
  for (const Hypothesis& h : hyps_) {
    const double m = std::exp(h.log_mass);
    if (m < opt_.converged_doubt && &h != &best()) continue;
    for (const Particle& p : h.particles) {
      const double w = m * std::exp(p.log_w);
      s += w * (p.pose.t - e.t).squaredNorm();
      wsum += w;
    }
  }
  return wsum > 0 ? std::sqrt(s / wsum) : 0.0;
}

void ParticleFilter::organise() {
  // Split: a broad hypothesis once its particles gathered into few modes, a tight one that came
  // apart (a rival place along a corridor). Modes below 1% of the weight are dropped.
  std::vector<Hypothesis> next;
  for (Hypothesis& h : hyps_) {
    const bool may_split = h.broad ? travelled_ - h.born_m >= opt_.split_after_m : h.spread > opt_.converged_spread;
    if (!may_split) {
      next.push_back(std::move(h));
      continue;
    }
    std::vector<detail::Mode> modes = detail::modesOf(h, opt_.cluster_cell, opt_.cluster_heading);
    std::size_t keep = 0;
    double covered = 0, in_modes = 0;
    for (const detail::Mode& m : modes) in_modes += m.weight;
    while (keep < modes.size() && (covered < 0.99 * in_modes || modes[keep].weight >= 0.01 * in_modes))
      covered += modes[keep++].weight;
    if ((h.broad && keep > static_cast<std::size_t>(opt_.max_hypotheses)) || (!h.broad && keep < 2)) {
      next.push_back(std::move(h));
      continue;
    }
    // A broad hypothesis also keeps the light modes whose best particle explains the last scan
    // about as well as the best mode's: a look-alike place (a symmetric twin) that sampling left
    // with few particles is a rival until the scans tell them apart.
    std::vector<std::size_t> kept(keep);
    std::iota(kept.begin(), kept.end(), std::size_t{0});
    if (h.broad && h.last_ll.size() == h.particles.size()) {
      std::vector<double> best(modes.size(), -std::numeric_limits<double>::infinity());
      for (std::size_t m = 0; m < modes.size(); ++m)
        for (std::size_t i : modes[m].members) best[m] = std::max(best[m], h.last_ll[i]);
      const double top = *std::max_element(best.begin(), best.end());
      std::vector<std::size_t> rivals;
      for (std::size_t m = keep; m < modes.size(); ++m)
        if (best[m] >= top - opt_.split_nats) rivals.push_back(m);
      std::stable_sort(rivals.begin(), rivals.end(), [&](std::size_t a, std::size_t b) { return best[a] > best[b]; });
      for (std::size_t m : rivals)
        if (kept.size() < static_cast<std::size_t>(opt_.max_hypotheses)) kept.push_back(m);
    }
    // The children take the untempered posterior: their particles' weights and their masses.
    std::vector<double> lu(h.particles.size());
    for (std::size_t i = 0; i < lu.size(); ++i)
      lu[i] = h.particles[i].log_w + (h.log_ratio.size() == lu.size() ? h.log_ratio[i] : 0.0);
    const double lu_norm = detail::logSumExp(lu);
    for (double& v : lu) v -= lu_norm;
    std::vector<Hypothesis> children;
    for (std::size_t m : kept) {
      Hypothesis c;
      c.broad = false;
      c.probe = h.probe;
      c.fit = h.fit;
      c.held_m = h.held_m;
      c.born_m = h.born_m;
      c.id = m == 0 ? h.id : next_id_++;
      std::vector<double> member_lu;
      for (std::size_t i : modes[m].members) member_lu.push_back(lu[i]);
      const double lw = detail::logSumExp(member_lu);
      c.log_mass = h.log_mass + std::max(lw, std::log(0.01));
      for (std::size_t i : modes[m].members) c.particles.push_back({h.particles[i].pose, lu[i] - lw});
      detail::summarise(c);
      children.push_back(std::move(c));
    }
    // A broad hypothesis splits only into compact modes: one still stretched along a corridor
    // stays annealed until the scans tell its places apart.
    const bool compact = std::all_of(children.begin(), children.end(),
                                     [&](const Hypothesis& c) { return c.spread <= 2.0 * opt_.cluster_cell; });
    if (h.broad && !compact) {
      next_id_ -= kept.size() - 1;  // the ids were not used
      next.push_back(std::move(h));
      continue;
    }
    for (Hypothesis& c : children) next.push_back(std::move(c));
  }
  hyps_ = std::move(next);
  // Merge tight hypotheses at the same place into the heavier.
  std::sort(hyps_.begin(), hyps_.end(), [](const Hypothesis& a, const Hypothesis& b) {
    return a.log_mass > b.log_mass || (a.log_mass == b.log_mass && a.id < b.id);
  });
  for (std::size_t i = 0; i < hyps_.size(); ++i) {
    if (hyps_[i].broad || hyps_[i].particles.empty()) continue;
    for (std::size_t j = i + 1; j < hyps_.size(); ++j) {
      Hypothesis& a = hyps_[i];
      Hypothesis& b = hyps_[j];
      if (b.broad || b.particles.empty()) continue;
      if ((a.estimate.t - b.estimate.t).norm() > opt_.merge_distance ||
          std::abs(angleDiff(a.estimate.theta, b.estimate.theta)) > opt_.merge_heading)
        continue;
      const double m = std::max(a.log_mass, b.log_mass);
      const double total = m + std::log(std::exp(a.log_mass - m) + std::exp(b.log_mass - m));
      for (Particle& p : a.particles) p.log_w += a.log_mass - total;
      for (const Particle& p : b.particles) a.particles.push_back({p.pose, p.log_w + b.log_mass - total});
      a.log_mass = total;
      a.probe = a.probe && b.probe;
      a.held_m = std::max(a.held_m, b.held_m);
      b.particles.clear();
      detail::summarise(a);
    }
  }
  // A probe's places may not lead while they explain the scans worse than tracking usually does,
  // nor jump an estimate tracked from a known start elsewhere without a break in the scans (or a
  // long doubt): its mass is held just under the best of the others.
  double lead_other = -std::numeric_limits<double>::infinity();
  const Hypothesis* tracked = nullptr;
  for (const Hypothesis& h : hyps_)
    if (!h.probe && !h.particles.empty() && h.log_mass > lead_other) {
      lead_other = h.log_mass;
      tracked = &h;
    }
  if (std::isfinite(lead_other) && w_slow_ > 0) {
    const Pose2 at = tracked->estimate;
    for (Hypothesis& h : hyps_) {
      if (!h.probe) continue;
      const bool fits = h.fit >= opt_.probe_fit * w_slow_;
      // A place near the tracked estimate is a correction the odometry could have needed, not a jump.
      const bool near = !h.broad && (h.estimate.t - at.t).norm() <= opt_.jump_m &&
                        std::abs(angleDiff(h.estimate.theta, at.theta)) <= opt_.jump_heading;
      if (fits && !near && guarded() && !licensed(h)) {
        // Held back by the guard alone: the travel over which it gained on the tracked estimate.
        if (!h.broad && h.log_mass > lead_other - 1.0) h.held_m += step_m_;
        if (!licensed(h)) h.log_mass = std::min(h.log_mass, lead_other - 1.0);
      } else if (!fits || (h.broad && guarded())) {
        // Nor may a probe still spread over the floor take over a tracked estimate: its places are
        // not yet told apart (along a corridor, one fits as well as its mirror image).
        h.log_mass = std::min(h.log_mass, lead_other - 1.0);
      }
    }
  }
  // Prune: empty, far below the best, probes past their life, beyond the count (but never the
  // tracked estimate: a probe split into max_hypotheses places, heavier before the hold above,
  // would push it out of the filter).
  const std::uint64_t tracked_id = tracked ? tracked->id : 0;
  double top = -std::numeric_limits<double>::infinity();
  for (const Hypothesis& h : hyps_)
    if (!h.particles.empty()) top = std::max(top, h.log_mass);
  std::vector<Hypothesis> kept;
  for (Hypothesis& h : hyps_) {
    const bool is_top = h.log_mass == top;
    // A probe's place that has not won within its life is dropped, unless it still holds a doubt
    // that counts against convergence (converged_doubt): a look-alike place the scans never told
    // apart from the estimate (a symmetric corridor) stays a rival, and the answer unsure.
    const bool doubt = !h.broad && h.log_mass >= top + std::log(opt_.converged_doubt);
    // A broad probe is not judged by its mass until it has gathered into places (split): its
    // first scans pay for the whole floor it samples.
    const bool dead = h.particles.empty() || (!h.broad && h.log_mass < top - opt_.prune_nats) ||
                      (h.probe && !is_top && !doubt && travelled_ - h.born_m > opt_.probe_life_m) ||
                      (kept.size() >= static_cast<std::size_t>(opt_.max_hypotheses) && h.id != tracked_id);
    if (!dead) {
      kept.push_back(std::move(h));
    } else if (h.probe && !h.particles.empty()) {
      probe_ended_m_ = travelled_;
    }
  }
  hyps_ = std::move(kept);
  // Normalise the masses.
  std::vector<double> lm;
  for (const Hypothesis& h : hyps_) lm.push_back(h.log_mass);
  const double lse = detail::logSumExp(lm);
  for (Hypothesis& h : hyps_) h.log_mass -= lse;
}

bool ParticleFilter::resample(Hypothesis& h, bool is_best, bool force) {
  const std::size_t n = h.particles.size();
  if (n == 0) return false;
  std::vector<double> w(n);
  double s2 = 0;
  for (std::size_t i = 0; i < n; ++i) {
    w[i] = std::exp(h.particles[i].log_w);
    s2 += w[i] * w[i];
  }
  const double ess = s2 > 0 ? 1.0 / s2 : 0.0;
  const auto global = globalParticles();
  // A broad hypothesis keeps the count it was made with (a probe of a trusted estimate is smaller).
  std::size_t count = h.broad ? std::min(global, n) : static_cast<std::size_t>(opt_.max_particles);
  const std::size_t lo =
      std::min(count, static_cast<std::size_t>(h.broad   ? std::max<std::size_t>(opt_.min_particles, global / 10)
                                               : is_best ? opt_.min_particles
                                                         : opt_.min_hypothesis_particles));
  // A hypothesis that grew by a merge is brought back to its bound even when its ESS is high.
  if (!force && ess >= opt_.resample_ess * static_cast<double>(n) && n <= count) return false;
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  if (opt_.adaptive && !h.broad) {  // a broad hypothesis keeps its count: its modes need it
    // KLD sampling (table 8.4): draw until the count covers the bins the draws occupy.
    std::vector<double> cdf(n);
    std::partial_sum(w.begin(), w.end(), cdf.begin());
    std::unordered_set<std::int64_t> bins;
    std::size_t drawn = 0;
    while (drawn < count) {
      const double r = u01(rng_) * cdf.back();
      const std::size_t i = std::min<std::size_t>(
          static_cast<std::size_t>(std::lower_bound(cdf.begin(), cdf.end(), r) - cdf.begin()), n - 1);
      bins.insert(detail::binKey(h.particles[i].pose, opt_.kld_bin_xy, opt_.kld_bin_theta));
      ++drawn;
      if (drawn >= lo && drawn >= kldBound(bins.size(), opt_.kld_epsilon, opt_.kld_z)) break;
    }
    count = std::max(drawn, lo);
  }
  std::vector<Particle> next;
  next.reserve(count);
  const double u = u01(rng_) / static_cast<double>(count);
  const bool ratios = h.log_ratio.size() == n;
  std::vector<double> next_ratio;
  for (std::size_t i : lowVarianceResample(w, count, u)) {
    next.push_back({h.particles[i].pose, 0.0});
    if (ratios) next_ratio.push_back(h.log_ratio[i]);
  }
  h.log_ratio = std::move(next_ratio);
  const double log_w = -std::log(static_cast<double>(next.size()));
  for (Particle& p : next) p.log_w = log_w;
  h.particles = std::move(next);
  return true;
}

}  // namespace glassmap::localize
