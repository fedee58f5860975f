#include "glassmap/localize/particle_filter.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <unordered_map>
#include <unordered_set>

#include "glassmap/core/error.hpp"
#include "glassmap/sensor/field_model.hpp"

namespace glassmap::localize {
namespace {

double logSumExp(const std::vector<double>& v) {
  double m = -std::numeric_limits<double>::infinity();
  for (double x : v) m = std::max(m, x);
  if (!std::isfinite(m)) return m;
  double s = 0.0;
  for (double x : v) s += std::exp(x - m);
  return m + std::log(s);
}

VectorMap wallsOf(const VectorMap& map) {
  VectorMap walls;
  for (const MapSegment& s : map.segments)
    if (s.material == Material::Wall) walls.segments.push_back(s);
  return walls;
}

std::int64_t binKey(const Pose2& p, double bin_xy, double bin_theta) {
  const auto ix = static_cast<std::int64_t>(std::floor(p.x() / bin_xy));
  const auto iy = static_cast<std::int64_t>(std::floor(p.y() / bin_xy));
  const auto it = static_cast<std::int64_t>(std::floor((p.theta + kPi) / bin_theta));
  return ((ix & 0xFFFFF) << 40) | ((iy & 0xFFFFF) << 20) | (it & 0xFFFFF);
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
    : model_(model), opt_(options), rng_(options.seed), walls_(wallsOf(model.map())) {
  if (opt_.max_particles < 1) throw Error("the particle count must be positive", {}, 0, "particles");
  opt_.min_particles = std::clamp(opt_.min_particles, 1, opt_.max_particles);
  collectFreeCells();
}

void ParticleFilter::collectFreeCells() {
  // Free space: cells of the map's bounding box at least free_clearance from every segment, and
  // within free_reach of some segment's box (a robot farther from everything sees nothing; a
  // stray segment far away must not fill the void between it and the building with cells).
  const VectorMap& map = model_.map();
  Eigen::AlignedBox2d box;
  for (const MapSegment& s : map.segments)
    if (s.a.allFinite() && s.b.allFinite()) {
      box.extend(s.a);
      box.extend(s.b);
    }
  if (box.isEmpty()) return;
  const sensor::DistanceGrid grid(map, true, free_cell_, std::max(opt_.free_clearance, free_cell_));
  // Coarse blocks within reach of a segment's box; at most 2048 a side.
  const double reach = std::max(opt_.free_reach, free_cell_);
  const Vec2 extent = box.max() - box.min();
  const double block = std::max({reach / 2.0, extent.x() / 2048.0, extent.y() / 2048.0});
  const int bx = std::max(1, static_cast<int>(std::ceil(extent.x() / block)) + 1);
  const int by = std::max(1, static_cast<int>(std::ceil(extent.y() / block)) + 1);
  std::vector<std::uint8_t> near(static_cast<std::size_t>(bx) * static_cast<std::size_t>(by), 0);
  auto blockOf = [&](double v, double lo, int n) {
    return std::clamp(static_cast<int>(std::floor((v - lo) / block)), 0, n - 1);
  };
  for (const MapSegment& s : map.segments) {
    if (!s.a.allFinite() || !s.b.allFinite()) continue;
    const Vec2 lo = s.a.cwiseMin(s.b) - Vec2::Constant(reach), hi = s.a.cwiseMax(s.b) + Vec2::Constant(reach);
    for (int j = blockOf(lo.y(), box.min().y(), by); j <= blockOf(hi.y(), box.min().y(), by); ++j)
      for (int i = blockOf(lo.x(), box.min().x(), bx); i <= blockOf(hi.x(), box.min().x(), bx); ++i)
        near[static_cast<std::size_t>(j) * static_cast<std::size_t>(bx) + static_cast<std::size_t>(i)] = 1;
  }
  // Cell centres x_k = min + (k + 1/2) * cell below max, row by row, in increasing x; only the
  // cells of blocks near a segment are visited.
  const Vec2 c0 = box.min() + Vec2::Constant(free_cell_ / 2);
  auto count = [&](double from, double to) {
    return from < to ? static_cast<long long>(std::ceil((to - from) / free_cell_)) : 0LL;
  };
  const long long nx = count(c0.x(), box.max().x()), ny = count(c0.y(), box.max().y());
  // Up to 4M cells a side the centres are accumulated step by step, as the full scan over the box
  // always did (bit for bit the same cells, so the same random particles); beyond, x0 + k * cell.
  constexpr long long kAccumulated = 4LL << 20;
  std::vector<double> xs, ys;
  if (nx <= kAccumulated)
    for (double x = c0.x(); x < box.max().x(); x += free_cell_) xs.push_back(x);
  if (ny <= kAccumulated)
    for (double y = c0.y(); y < box.max().y(); y += free_cell_) ys.push_back(y);
  auto centre = [&](const std::vector<double>& acc, double first, long long k) {
    return k < static_cast<long long>(acc.size()) ? acc[static_cast<std::size_t>(k)]
                                                  : first + static_cast<double>(k) * free_cell_;
  };
  // At most 50M cells (800 MB): a map whose segments reach further is refused, not swapped.
  constexpr double kMaxFreeCells = 50e6;
  double estimate = 0.0;
  for (int j = 0; j < by; ++j)
    for (int i = 0; i < bx; ++i)
      estimate += near[static_cast<std::size_t>(j) * static_cast<std::size_t>(bx) + static_cast<std::size_t>(i)];
  estimate *= (block / free_cell_) * (block / free_cell_);
  if (estimate > kMaxFreeCells)
    throw Error("the map's free space within " + std::to_string(static_cast<int>(reach)) +
                    " m of its segments is about " + std::to_string(static_cast<long long>(estimate / 1e6)) +
                    "M cells of " + std::to_string(free_cell_) +
                    " m (limit 50M): segments spread over an implausible area",
                {}, 0, "segments");
  for (int j = 0; j < by; ++j) {
    const std::size_t row = static_cast<std::size_t>(j) * static_cast<std::size_t>(bx);
    if (std::find(near.begin() + static_cast<std::ptrdiff_t>(row),
                  near.begin() + static_cast<std::ptrdiff_t>(row + static_cast<std::size_t>(bx)),
                  1) == near.begin() + static_cast<std::ptrdiff_t>(row + static_cast<std::size_t>(bx)))
      continue;
    const long long ky0 = std::max(0LL, static_cast<long long>(std::floor(j * block / free_cell_)) - 2);
    const long long ky1 = std::min(ny, static_cast<long long>(std::ceil((j + 1) * block / free_cell_)) + 2);
    for (long long ky = ky0; ky < ky1; ++ky) {
      const double y = centre(ys, c0.y(), ky);
      if (!(y < box.max().y()) || blockOf(y, box.min().y(), by) != j) continue;
      for (int i = 0; i < bx; ++i) {
        if (!near[row + static_cast<std::size_t>(i)]) continue;
        const long long k0 = std::max(0LL, static_cast<long long>(std::floor(i * block / free_cell_)) - 2);
        const long long k1 = std::min(nx, static_cast<long long>(std::ceil((i + 1) * block / free_cell_)) + 2);
        for (long long k = k0; k < k1; ++k) {
          const double x = centre(xs, c0.x(), k);
          if (!(x < box.max().x()) || blockOf(x, box.min().x(), bx) != i) continue;
          if (grid.distance({x, y}) >= opt_.free_clearance) free_cells_.emplace_back(x, y);
        }
      }
    }
  }
}

Pose2 ParticleFilter::randomFreePose() {
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const double heading = (2.0 * u01(rng_) - 1.0) * kPi;
  if (free_cells_.empty()) {
    const Eigen::AlignedBox2d box = model_.map().bounds();
    if (box.isEmpty()) return {0.0, 0.0, heading};
    return {box.min() + (box.max() - box.min()).cwiseProduct(Vec2(u01(rng_), u01(rng_))), heading};
  }
  std::uniform_int_distribution<std::size_t> pick(0, free_cells_.size() - 1);
  const Vec2 c = free_cells_[pick(rng_)];
  return {c + free_cell_ * Vec2(u01(rng_) - 0.5, u01(rng_) - 0.5), heading};
}

void ParticleFilter::initialize(const Pose2& pose, double sigma_xy, double sigma_theta) {
  std::normal_distribution<double> n01(0.0, 1.0);
  particles_.resize(static_cast<std::size_t>(opt_.max_particles));
  const double log_w = -std::log(static_cast<double>(particles_.size()));
  for (Particle& p : particles_) {
    p.pose = Pose2(pose.t + sigma_xy * Vec2(n01(rng_), n01(rng_)), pose.theta + sigma_theta * n01(rng_));
    p.log_w = log_w;
  }
  w_slow_ = w_fast_ = 0.0;
  contradiction_ = 0.0;
  known_start_ = true;
  annealing_ = false;
}

void ParticleFilter::initializeGlobal() {
  particles_.resize(static_cast<std::size_t>(opt_.max_particles));
  const double log_w = -std::log(static_cast<double>(particles_.size()));
  for (Particle& p : particles_) {
    p.pose = randomFreePose();
    p.log_w = log_w;
  }
  w_slow_ = w_fast_ = 0.0;
  contradiction_ = 0.0;
  known_start_ = false;
  converged_at_ = -1.0;
  annealing_ = opt_.global_temperature > 1.0;
  travelled_ = 0.0;
}

void ParticleFilter::predict(const OdometryDelta& delta) {
  travelled_ += std::abs(delta.trans);
  for (Particle& p : particles_) p.pose = sampleMotionOdometry(p.pose, delta, opt_.noise, rng_);
}

void ParticleFilter::normalise() {
  scratch_.resize(particles_.size());
  for (std::size_t i = 0; i < particles_.size(); ++i) scratch_[i] = particles_[i].log_w;
  const double lse = logSumExp(scratch_);
  for (Particle& p : particles_) p.log_w -= lse;
}

double ParticleFilter::effectiveSampleSize() const {
  double s = 0.0;
  for (const Particle& p : particles_) s += std::exp(2.0 * p.log_w);
  return s > 0 ? 1.0 / s : 0.0;
}

bool ParticleFilter::correct(const sensor::BeamSet& beams) {
  if (particles_.empty() || beams.size() == 0) return false;
  const std::size_t n = particles_.size();
  std::vector<double> ll(n);
  // Weighting is the only parallel step: each particle's likelihood is a pure function of its
  // pose, so results do not depend on the thread count.
  poses_.resize(n);
  for (std::size_t i = 0; i < n; ++i) poses_[i] = particles_[i].pose;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 64), [&](const tbb::blocked_range<std::size_t>& r) {
    model_.logLikelihoods(std::span<const Pose2>(poses_).subspan(r.begin(), r.size()), beams, &ll[r.begin()]);
  });
  if (annealing_)
    for (double& v : ll) v /= opt_.global_temperature;
  // Marginal likelihood of the scan under the prior weights, per beam (a geometric mean keeps it in
  // range for any beam count): the augmented-MCL averages track it (table 8.3).
  for (std::size_t i = 0; i < n; ++i) {
    particles_[i].log_w += ll[i];
    ll[i] = particles_[i].log_w;
  }
  const double log_marginal = logSumExp(ll);
  const double w_avg = std::exp(log_marginal / static_cast<double>(beams.size()));
  if (w_slow_ <= 0.0) {
    w_slow_ = w_fast_ = w_avg;
  } else {
    w_slow_ += opt_.alpha_slow * (w_avg - w_slow_);
    w_fast_ += opt_.alpha_fast * (w_avg - w_fast_);
  }
  for (Particle& p : particles_) p.log_w -= log_marginal;
  if (opt_.inject_only_when_contradicted && !annealing_) {
    // Readings through a wall at the best particle: what no clutter can explain.
    const auto best = std::max_element(particles_.begin(), particles_.end(),
                                       [](const Particle& a, const Particle& b) { return a.log_w < b.log_w; });
    const Eigen::Matrix2d R = best->pose.rotation();
    std::size_t valid = 0, through = 0;
    for (std::size_t i = 0; i < beams.size(); ++i) {
      const double z = beams.ranges[i];
      if (!(z < beams.max_range)) continue;
      ++valid;
      const double e = walls_.castRange(best->pose.t, R * beams.dirs[i], beams.max_range);
      through += z > e + opt_.contradiction_gate;
    }
    if (valid > 0) {
      const double share = static_cast<double>(through) / static_cast<double>(valid);
      contradiction_ += opt_.contradiction_rate * (share - contradiction_);
    }
  }
  // A collapse of the likelihood to a fiftieth of its average (kidnapping) restarts the cloud
  // whatever the walls say: a robot carried to a place that looks like where it was (a symmetric
  // room) contradicts no wall. Milder drops only inject while the map contradicts the estimate.
  if (opt_.inject && !annealing_ && opt_.relocalize_ratio > 0 && w_fast_ < opt_.relocalize_ratio * w_slow_) {
    // Kidnapped or hopelessly lost: a few random particles over a whole floor rarely land near
    // the robot; start over with a full global cloud.
    initializeGlobal();
    ++relocalizations_;
    last_injected_ = particles_.size();
    return true;
  }
  // No injection while annealing: the whole cloud is still a set of random guesses.
  const double p_inject = mayRecover() ? std::max(0.0, 1.0 - w_fast_ / w_slow_) : 0.0;
  if (effectiveSampleSize() < opt_.resample_ess * static_cast<double>(n) || p_inject > 0.05) {
    resample();
    if (annealing_ && travelled_ >= opt_.anneal_min_travel && spread() < opt_.converged_spread) {
      annealing_ = false;
      converged_at_ = travelled_;
      w_slow_ = w_fast_ = 0.0;  // the likelihood averages restart at the untempered scale
    }
    return true;
  }
  last_injected_ = 0;
  return false;
}

bool ParticleFilter::mayRecover() const {
  if (!opt_.inject || annealing_) return false;
  const bool trusted = known_start_ || (converged_at_ >= 0 && travelled_ - converged_at_ >= opt_.trust_after_m);
  return !opt_.inject_only_when_contradicted || !trusted || contradiction_ > opt_.contradiction_share;
}

void ParticleFilter::resample() {
  const std::size_t n = particles_.size();
  std::vector<double> w(n);
  for (std::size_t i = 0; i < n; ++i) w[i] = std::exp(particles_[i].log_w);
  std::uniform_real_distribution<double> u01(0.0, 1.0);

  std::size_t count = static_cast<std::size_t>(opt_.max_particles);
  if (opt_.adaptive) {
    // KLD sampling (table 8.4): draw until the count covers the bins the draws occupy.
    std::vector<double> cdf(n);
    std::partial_sum(w.begin(), w.end(), cdf.begin());
    std::unordered_set<std::int64_t> bins;
    std::size_t drawn = 0;
    const auto lo = static_cast<std::size_t>(annealing_ ? std::max(opt_.min_particles, opt_.max_particles / 10)
                                                        : opt_.min_particles);
    while (drawn < count) {
      const double r = u01(rng_) * cdf.back();
      const std::size_t i = std::min<std::size_t>(
          static_cast<std::size_t>(std::lower_bound(cdf.begin(), cdf.end(), r) - cdf.begin()), n - 1);
      bins.insert(binKey(particles_[i].pose, opt_.kld_bin_xy, opt_.kld_bin_theta));
      ++drawn;
      if (drawn >= lo && drawn >= kldBound(bins.size(), opt_.kld_epsilon, opt_.kld_z)) break;
    }
    count = std::max(drawn, lo);
  }
  const double p_inject = mayRecover() && w_slow_ > 0 ? std::max(0.0, 1.0 - w_fast_ / w_slow_) : 0.0;
  const auto injected = static_cast<std::size_t>(std::floor(p_inject * static_cast<double>(count)));
  const std::size_t kept = count - injected;
  std::vector<Particle> next;
  next.reserve(count);
  if (kept > 0) {
    const double u = u01(rng_) / static_cast<double>(kept);
    for (std::size_t i : lowVarianceResample(w, kept, u)) next.push_back({particles_[i].pose, 0.0});
  }
  for (std::size_t k = 0; k < injected; ++k) next.push_back({randomFreePose(), 0.0});
  const double log_w = -std::log(static_cast<double>(next.size()));
  for (Particle& p : next) p.log_w = log_w;
  particles_ = std::move(next);
  last_injected_ = injected;
  // After an injection the averages restart, so one bad scan does not keep scattering particles.
  if (injected > 0) w_fast_ = w_slow_;
}

Pose2 ParticleFilter::estimate() const {
  if (particles_.empty()) return {};
  // Heaviest 1 m cell, then the weighted mean of the particles within 1 m of its mean.
  struct Acc {
    double w = 0;
    Vec2 s = Vec2::Zero();
  };
  std::unordered_map<std::int64_t, Acc> cells;
  for (const Particle& p : particles_) {
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
  const Vec2 centre = best->w > 0 ? Vec2(best->s / best->w) : particles_.front().pose.t;
  double wsum = 0, c = 0, s = 0;
  Vec2 t = Vec2::Zero();
  for (const Particle& p : particles_) {
    if ((p.pose.t - centre).norm() > 1.0) continue;
    const double w = std::exp(p.log_w);
    wsum += w;
    t += w * p.pose.t;
    c += w * std::cos(p.pose.theta);
    s += w * std::sin(p.pose.theta);
  }
  if (wsum <= 0) return particles_.front().pose;
  return {t / wsum, std::atan2(s, c)};
}

double ParticleFilter::spread() const {
  const Pose2 e = estimate();
  double s = 0, wsum = 0;
  for (const Particle& p : particles_) {
    const double w = std::exp(p.log_w);
    s += w * (p.pose.t - e.t).squaredNorm();
    wsum += w;
  }
  return wsum > 0 ? std::sqrt(s / wsum) : 0.0;
}

}  // namespace glassmap::localize
