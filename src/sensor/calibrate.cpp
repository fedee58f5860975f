#include "glassmap/sensor/calibrate.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numeric>
#include <string>

#include <Eigen/Dense>

#include "glassmap/core/angles.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/geometry/ray_caster.hpp"
#include "glassmap/glass/scan_coherence.hpp"
#include "nelder_mead.hpp"
#include "range_noise.hpp"

namespace glassmap::sensor {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// A beam whose first surface in the map is a wall.
struct WallBeam {
  float e;         // expected range [m]
  float z;         // reading [m]; >= z_max: a max reading
  float z_max;     // [m]
  bool fit_sigma;  // incidence within max_fit_incidence_deg
};

// A beam whose first surface is glass, with its three modes (no refraction offset).
struct GlassBeam {
  float theta_deg;
  float z;               // reading [m], +inf for max / no return
  float d_g;             // range to the pane [m]
  float e_mirror;        // along the mirrored ray [m], +inf when nothing is met
  float e_through;       // along the continued ray to a wall [m], +inf when nothing is met
  int panes;             // panes crossed by the continued ray
  std::int32_t segment;  // the pane's index in the map
  std::uint32_t scan;    // the scan's index among those used
};

struct ScanRecords {
  std::vector<detail::RangeResidual> in_scan;  // residuals of neighbouring returns (range_noise.hpp)
  std::vector<WallBeam> walls;
  std::vector<GlassBeam> glass;
  bool aligned = false;
  double shift_m = 0.0, turn_deg = 0.0;
};

Vec2 unit(double a) { return {std::cos(a), std::sin(a)}; }

// Point-to-line Gauss-Newton of one scan's pose against the walls, damped towards the logged pose
// (a scan that sees one wall only keeps its logged position along it).
bool alignScan(const RayCaster& caster, const LaserScan& scan, const CalibrationOptions& o, Pose2& pose) {
  const Pose2 logged = pose;
  constexpr double kScale = 0.03;  // residual scale [m] (Huber corner at 2 kScale)
  const double prior_xy = 0.10, prior_th = deg2rad(2.0);
  const double max_inc = deg2rad(70.0);
  for (int iter = 0; iter < 6; ++iter) {
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    int used = 0;
    const Eigen::Matrix2d R = pose.rotation();
    for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
      if (!scan.isReturn(i) || scan.ranges[i] < 0.05f) continue;
      const Vec2 d = R * unit(scan.beamAngle(i));
      const RayHit hit = caster.cast(pose.t, d, scan.max_range);
      if (!hit.hit() || hit.material != Material::Wall || hit.incidence > max_inc) continue;
      const double z = scan.ranges[i];
      if (std::abs(z - hit.range) > o.align_gate_m) continue;
      const MapSegment& s = caster.map().segments[static_cast<std::size_t>(hit.segment)];
      const Vec2 t = s.direction();
      const Vec2 n(-t.y(), t.x());
      const Vec2 rq = z * d;  // R q
      const double r = n.dot(pose.t + rq - s.a);
      const Eigen::Vector3d J(n.x(), n.y(), n.dot(Vec2(-rq.y(), rq.x())));
      const double w = std::abs(r) <= 2 * kScale ? 1.0 : 2 * kScale / std::abs(r);
      H += (w / (kScale * kScale)) * J * J.transpose();
      g += (w / (kScale * kScale)) * r * J;
      ++used;
    }
    if (used < 20) {
      pose = logged;
      return false;
    }
    const Eigen::Vector3d dev(pose.t.x() - logged.t.x(), pose.t.y() - logged.t.y(),
                              wrapAngle(pose.theta - logged.theta));
    const Eigen::Vector3d prior(1 / (prior_xy * prior_xy), 1 / (prior_xy * prior_xy), 1 / (prior_th * prior_th));
    H += prior.asDiagonal();
    g += prior.cwiseProduct(dev);
    const Eigen::Vector3d step = -H.ldlt().solve(g);
    if (!step.allFinite()) {
      pose = logged;
      return false;
    }
    pose = Pose2(pose.t + step.head<2>(), pose.theta + step.z());
    if (step.head<2>().norm() < 1e-5 && std::abs(step.z()) < 1e-6) break;
  }
  return true;
}

// The glass modes of a beam hitting pane `hit` (offset 0): mirrored and continued ranges.
GlassBeam glassModes(const RayCaster& caster, const Vec2& origin, const Vec2& dir, const RayHit& hit, double z_max) {
  GlassBeam b{};
  b.theta_deg = static_cast<float>(rad2deg(hit.incidence));
  b.d_g = static_cast<float>(hit.range);
  const Vec2 p = origin + hit.range * dir;
  const MapSegment& pane = caster.map().segments[static_cast<std::size_t>(hit.segment)];
  const Vec2 t = pane.direction();
  const Vec2 mirrored = 2.0 * dir.dot(t) * t - dir;
  b.e_mirror = static_cast<float>(hit.range + caster.castRange(p, mirrored, z_max - hit.range, hit.segment));
  b.e_through = static_cast<float>(kInf);
  b.panes = 1;
  Vec2 o = p;
  double travelled = hit.range;
  std::int32_t skip = hit.segment;
  for (int k = 0; k < 4; ++k) {
    const RayHit next = caster.cast(o, dir, z_max - travelled, skip);
    if (!next.hit()) break;
    travelled += next.range;
    if (next.material == Material::Wall) {
      b.e_through = static_cast<float>(travelled);
      break;
    }
    ++b.panes;
    o = o + next.range * dir;
    skip = next.segment;
  }
  return b;
}

ScanRecords collect(const RayCaster& caster, const LaserScan& scan, std::uint32_t index, const CalibrationOptions& o) {
  ScanRecords rec;
  if (o.sigma_source != SigmaSource::Prior) detail::inScanResiduals(scan, rec.in_scan);
  Pose2 pose = scan.laser_pose;
  if (o.align_scans) {
    rec.aligned = alignScan(caster, scan, o, pose);
    rec.shift_m = (pose.t - scan.laser_pose.t).norm();
    rec.turn_deg = std::abs(rad2deg(wrapAngle(pose.theta - scan.laser_pose.theta)));
  }
  const Eigen::Matrix2d R = pose.rotation();
  const double z_max = scan.max_range;
  if (!(z_max > 0)) return rec;
  const double cos_fit = std::cos(deg2rad(o.max_fit_incidence_deg));
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    const float raw = scan.ranges[i];
    if (std::isfinite(raw) && raw < 0.05f && raw >= 0) continue;  // dead zone
    const float z = scan.isReturn(i) ? raw : static_cast<float>(kInf);
    const Vec2 d = R * unit(scan.beamAngle(i));
    const RayHit hit = caster.cast(pose.t, d, z_max);
    if (!hit.hit() || hit.range > 0.95 * z_max) continue;  // no surface within range: tells nothing
    if (hit.material == Material::Wall) {
      rec.walls.push_back({static_cast<float>(hit.range), std::min(z, static_cast<float>(z_max)),
                           static_cast<float>(z_max), std::cos(hit.incidence) >= cos_fit});
    } else {
      // Pane ends are where a floorplan is least sure (a pane drawn a little long ends on a wall,
      // whose returns would pass for direct returns at any angle): only beams meeting a pane
      // away from its ends count.
      const MapSegment& pane = caster.map().segments[static_cast<std::size_t>(hit.segment)];
      const Vec2 at = pose.t + hit.range * d;
      if (std::min((at - pane.a).norm(), (at - pane.b).norm()) < o.pane_end_margin_m) continue;
      GlassBeam b = glassModes(caster, pose.t, d, hit, z_max);
      b.z = z;
      b.segment = hit.segment;
      b.scan = index;
      rec.glass.push_back(b);
    }
  }
  return rec;
}

// EM over the beam-model mixture (Probabilistic Robotics table 6.2).
void fitBeamModel(const std::vector<WallBeam>& beams, const CalibrationOptions& o, SensorProfile& p,
                  std::vector<std::string>& warnings) {
  if (beams.size() < 500) {
    warnings.push_back("only " + std::to_string(beams.size()) +
                       " beams on walls: the beam model keeps its prior values");
    return;
  }
  double w[4] = {p.w_hit.value, p.w_short.value, p.w_max.value, p.w_rand.value};
  for (double& x : w) x = std::max(x, 0.01);
  double sigma = std::max(p.range_sigma_m.value, 0.005), lambda = std::max(p.lambda_short.value, 0.01);
  double n_eff[4] = {0, 0, 0, 0}, n_sigma = 0;
  // The E step's sums in a fixed tree of fixed blocks: the same sums on any number of threads.
  struct Sums {
    double sum[4] = {0, 0, 0, 0};
    double sq = 0, sq_w = 0, short_z = 0;
  };
  for (int it = 0; it < o.em_iterations; ++it) {
    const double norm = 1.0 / (std::sqrt(2 * kPi) * sigma);
    const Sums s = tbb::parallel_deterministic_reduce(
        tbb::blocked_range<std::size_t>(0, beams.size(), 16384), Sums{},
        [&](const tbb::blocked_range<std::size_t>& r, Sums acc) {
          for (std::size_t i = r.begin(); i != r.end(); ++i) {
            const WallBeam& b = beams[i];
            double q[4];
            if (b.z >= b.z_max) {
              q[0] = q[1] = q[3] = 0;
              q[2] = w[2];
            } else {
              const double u = (b.z - b.e) / sigma;
              q[0] = w[0] * norm * std::exp(-0.5 * u * u);
              q[1] = b.z < b.e ? w[1] * lambda * std::exp(-lambda * b.z) / (-std::expm1(-lambda * b.e)) : 0.0;
              q[2] = 0;
              q[3] = w[3] / b.z_max;
            }
            const double total = q[0] + q[1] + q[2] + q[3];
            if (!(total > 0)) continue;
            for (int k = 0; k < 4; ++k) acc.sum[k] += q[k] / total;
            const double r_hit = q[0] / total;
            if (b.fit_sigma) {
              acc.sq += r_hit * (b.z - b.e) * (b.z - b.e);
              acc.sq_w += r_hit;
            }
            acc.short_z += q[1] / total * b.z;
          }
          return acc;
        },
        [](Sums a, const Sums& b) {
          for (int k = 0; k < 4; ++k) a.sum[k] += b.sum[k];
          a.sq += b.sq;
          a.sq_w += b.sq_w;
          a.short_z += b.short_z;
          return a;
        });
    const double* sum = s.sum;
    const double sq = s.sq, sq_w = s.sq_w, short_z = s.short_z;
    const double n = sum[0] + sum[1] + sum[2] + sum[3];
    double moved = 0;
    for (int k = 0; k < 4; ++k) {
      const double nw = std::max(sum[k] / n, 1e-6);
      moved = std::max(moved, std::abs(nw - w[k]));
      w[k] = nw;
      n_eff[k] = sum[k];
    }
    if (sq_w > 10) sigma = std::max(std::sqrt(sq / sq_w), 1e-4);
    if (short_z > 0 && sum[1] > 1) lambda = std::clamp(sum[1] / short_z, 1e-3, 50.0);
    n_sigma = sq_w;
    if (moved < 1e-6 && it > 5) break;
  }
  const double n = static_cast<double>(beams.size());
  Estimate* fields[4] = {&p.w_hit, &p.w_short, &p.w_max, &p.w_rand};
  for (int k = 0; k < 4; ++k) *fields[k] = {w[k], std::sqrt(w[k] * (1 - w[k]) / n), true};
  p.range_sigma_m = {sigma, sigma / std::sqrt(2.0 * std::max(n_sigma, 1.0)), true};
  p.lambda_short = {lambda, lambda / std::sqrt(std::max(n_eff[1], 1.0)), n_eff[1] > 30};
}

// Beams grouped by incidence angle for a binomial fit: (theta, trials, successes).
struct Binned {
  std::vector<double> theta, n, k;
};

Binned binBernoulli(const std::vector<std::pair<float, bool>>& obs, double width) {
  const int bins = static_cast<int>(std::ceil(90.0 / width));
  std::vector<double> n(static_cast<std::size_t>(bins), 0.0), k(static_cast<std::size_t>(bins), 0.0),
      s(static_cast<std::size_t>(bins), 0.0);
  for (const auto& [theta, y] : obs) {
    const auto b = static_cast<std::size_t>(std::clamp(static_cast<int>(theta / width), 0, bins - 1));
    n[b] += 1;
    k[b] += y ? 1 : 0;
    s[b] += theta;
  }
  Binned out;
  for (std::size_t b = 0; b < n.size(); ++b) {
    if (n[b] == 0) continue;
    out.theta.push_back(s[b] / n[b]);
    out.n.push_back(n[b]);
    out.k.push_back(k[b]);
  }
  return out;
}

template <class Prob>
double binomialNll(const Binned& d, Prob&& prob) {
  double nll = 0;
  for (std::size_t i = 0; i < d.theta.size(); ++i) {
    const double p = std::clamp(prob(d.theta[i]), 1e-9, 1 - 1e-9);
    nll -= d.k[i] * std::log(p) + (d.n[i] - d.k[i]) * std::log1p(-p);
  }
  return nll;
}

// Standard errors from the inverse of the numeric Hessian of f at x (natural parameters).
template <std::size_t N, class F>
std::array<double, N> standardErrors(F&& f, const std::array<double, N>& x, const std::array<double, N>& step) {
  Eigen::Matrix<double, N, N> H;
  const double f0 = f(x);
  for (std::size_t i = 0; i < N; ++i)
    for (std::size_t j = i; j < N; ++j) {
      auto at = [&](double di, double dj) {
        std::array<double, N> y = x;
        y[i] += di;
        y[j] += dj;
        return f(y);
      };
      const double hi = step[i], hj = step[j];
      double v;
      if (i == j)
        v = (at(hi, 0) - 2 * f0 + at(-hi, 0)) / (hi * hi);
      else
        v = (at(hi, hj) - at(hi, -hj) - at(-hi, hj) + at(-hi, -hj)) / (4 * hi * hj);
      H(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = v;
      H(static_cast<Eigen::Index>(j), static_cast<Eigen::Index>(i)) = v;
    }
  std::array<double, N> se{};
  const Eigen::LDLT<Eigen::Matrix<double, N, N>> ldlt(H);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return se;
  const Eigen::Matrix<double, N, N> cov = ldlt.solve(Eigen::Matrix<double, N, N>::Identity());
  for (std::size_t i = 0; i < N; ++i) {
    const double v = cov(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(i));
    se[i] = v > 0 && std::isfinite(v) ? std::sqrt(v) : 0.0;
  }
  return se;
}

double logistic(double u) { return 1.0 / (1.0 + std::exp(-u)); }
double logit(double p) { return std::log(p / (1 - p)); }

void fitDirect(const Binned& d, SensorProfile& p) {
  auto prob = [](double peak, double sigma, double floor, double theta) {
    return floor + (peak - floor) * std::exp(-theta * theta / (2 * sigma * sigma));
  };
  // Unconstrained: peak = logistic(u0), sigma = exp(u1) [deg], floor = peak * logistic(u2).
  auto nll = [&](const std::array<double, 3>& u) {
    const double peak = logistic(u[0]), sigma = std::exp(std::clamp(u[1], -3.0, 5.0)), floor = peak * logistic(u[2]);
    return binomialNll(d, [&](double th) { return prob(peak, sigma, floor, th); });
  };
  std::array<double, 3> best{};
  double best_f = kInf;
  for (double s0 : {1.5, 4.0, 10.0, 20.0})
    for (double f0 : {0.005, 0.1}) {
      const auto r = nelderMead<3>(nll, {logit(0.8), std::log(s0), logit(f0)}, {1.0, 0.5, 1.5}, 600);
      if (r.value < best_f) best_f = r.value, best = r.x;
    }
  const double peak = logistic(best[0]), sigma = std::exp(std::clamp(best[1], -3.0, 5.0));
  const double floor = peak * logistic(best[2]);
  auto nat = [&](const std::array<double, 3>& x) {
    if (x[0] <= 0 || x[0] > 1 || x[1] <= 0 || x[2] < 0 || x[2] >= x[0]) return 1e300;
    return binomialNll(d, [&](double th) { return prob(x[0], x[1], x[2], th); });
  };
  const std::array<double, 3> x{peak, sigma, std::max(floor, 1e-4)};
  const auto se = standardErrors<3>(nat, x, {std::min(1e-3, 0.5 * (1 - peak)), 1e-2 * sigma, 0.5e-4});
  p.direct_peak = {peak, se[0], true};
  p.direct_sigma_deg = {sigma, se[1], true};
  p.direct_floor = {floor, se[2], true};
}

void fitMirror(const Binned& d, SensorProfile& p) {
  auto prob = [](double lambda, double floor, double theta) {
    return floor + (1 - floor) * std::exp(-lambda * (90.0 - theta));
  };
  auto nll = [&](const std::array<double, 2>& u) {
    const double lambda = std::exp(std::clamp(u[0], -12.0, 1.0)), floor = logistic(u[1]);
    return binomialNll(d, [&](double th) { return prob(lambda, floor, th); });
  };
  std::array<double, 2> best{};
  double best_f = kInf;
  for (double l0 : {0.01, 0.09})
    for (double f0 : {0.01, 0.3}) {
      const auto r = nelderMead<2>(nll, {std::log(l0), logit(f0)}, {0.7, 1.5}, 400);
      if (r.value < best_f) best_f = r.value, best = r.x;
    }
  const double lambda = std::exp(std::clamp(best[0], -12.0, 1.0)), floor = logistic(best[1]);
  auto nat = [&](const std::array<double, 2>& x) {
    if (x[0] <= 0 || x[1] < 0 || x[1] >= 1) return 1e300;
    return binomialNll(d, [&](double th) { return prob(x[0], x[1], th); });
  };
  const auto se = standardErrors<2>(nat, {lambda, std::max(floor, 1e-4)}, {1e-2 * lambda, 0.5e-4});
  p.normal_lambda_per_deg = {lambda, se[0], true};
  p.normal_floor = {floor, se[1], true};
}

// The scans a calibration uses: at most max_scans, spread evenly over the log, gathered in one
// pass (a spooled log is read once).
std::vector<LaserScan> pickScans(const LaserLog& log, std::size_t max_scans) {
  std::vector<std::size_t> picked;
  const std::size_t n = log.scanCount(), want = std::max<std::size_t>(1, std::min(max_scans, n));
  for (std::size_t k = 0; k < want; ++k) picked.push_back(k * n / want);
  std::vector<LaserScan> scans;
  scans.reserve(picked.size());
  forEachScanBlock(log, [&](std::span<const LaserScan> block, std::size_t first) {
    for (std::size_t k = scans.size(); k < picked.size() && picked[k] < first + block.size(); ++k)
      scans.push_back(block[picked[k] - first]);
  });
  return scans;
}

// The noise fit of neighbouring readings within scans (no map in it), as calibrate's Local source.
detail::RangeNoiseFit inScanFit(const std::vector<detail::RangeResidual>& in_scan) {
  return detail::fitRangeNoise(in_scan, 1.5, 500, true);
}

// The median range of the scans' returns [m]: where the log's readings typically are.
double medianReturnRange(const std::vector<LaserScan>& scans) {
  std::vector<double> ranges;
  for (const LaserScan& scan : scans)
    for (std::size_t i = 0; i < scan.ranges.size(); ++i)
      if (scan.isReturn(i) && scan.ranges[i] >= 0.05f) ranges.push_back(scan.ranges[i]);
  return detail::median(ranges);
}

// The panes of `map` whose near-normal beams return scan by scan, all or none, as a person walking
// by does (glass/scan_coherence.hpp): what a first pass drew as glass on people's arcs. Their beams
// would fit a lobe to people; the caller leaves them out. Counted, with a warning, in `result`.
template <class GateOf>
std::vector<bool> transientPanes(const std::vector<GlassBeam>& glass, const VectorMap& map, const CalibrationOptions& o,
                                 const GateOf& gateOf, CalibrationResult& result) {
  std::vector<bool> transient(map.segments.size(), false);
  if (!(o.max_transient_p > 0.0)) return transient;
  std::vector<glass::sparse::NearNormalBeam> near;
  for (const GlassBeam& b : glass) {
    if (b.theta_deg > o.transient_angle_deg) continue;
    const double gate = gateOf(b);
    if (b.z < b.d_g - gate) continue;  // short of the pane: neither returned nor passed
    near.push_back({static_cast<std::uint32_t>(b.segment), b.scan, static_cast<float>(deg2rad(b.theta_deg)),
                    std::abs(b.z - b.d_g) < gate});
  }
  const std::vector<glass::sparse::ScanCoherence> coherence =
      glass::sparse::scanCoherence(near, map.segments.size(), deg2rad(o.transient_bin_deg));
  double length = 0.0;
  for (std::size_t s = 0; s < coherence.size(); ++s) {
    if (!glass::sparse::isTransient(coherence[s], o.max_transient_p, o.min_transient_correlation)) continue;
    transient[s] = true;
    ++result.transient_panes;
    length += map.segments[s].length();
  }
  result.transient_length_m = length;
  if (result.transient_panes > 0) {
    char what[200];
    std::snprintf(what, sizeof what,
                  "%zu glass segment(s), %.1f m, answer scan by scan, all near-normal beams or none, as people "
                  "walking by do: left out of the glass fit",
                  result.transient_panes, length);
    result.warnings.push_back(what);
  }
  return transient;
}
}  // namespace

CalibrationResult calibrate(const LaserLog& log, const VectorMap& map, const CalibrationOptions& o) {
  if (log.scanCount() == 0) throw Error("the log has no scans to calibrate from");
  if (std::none_of(map.segments.begin(), map.segments.end(),
                   [](const MapSegment& s) { return s.material == Material::Wall; }))
    throw Error("the floorplan has no wall to calibrate against");
  const RayCaster caster(map);
  const std::vector<LaserScan> scans = pickScans(log, o.max_scans);
  std::vector<ScanRecords> records(scans.size());
  tbb::parallel_for(std::size_t{0}, scans.size(),
                    [&](std::size_t k) { records[k] = collect(caster, scans[k], static_cast<std::uint32_t>(k), o); });

  CalibrationResult result;
  result.profile = o.prior;
  result.scans = scans.size();
  std::vector<WallBeam> walls;
  std::vector<GlassBeam> glass;
  std::vector<double> shifts, turns;
  std::vector<detail::RangeResidual> in_scan;
  {
    std::size_t n_in_scan = 0, n_walls = 0, n_glass = 0;
    for (const ScanRecords& r : records) {
      n_in_scan += r.in_scan.size();
      n_walls += r.walls.size();
      n_glass += r.glass.size();
    }
    in_scan.reserve(n_in_scan);
    walls.reserve(n_walls);
    glass.reserve(n_glass);
  }
  // Each scan's records go as they are gathered (the log's records are held once, not twice).
  for (ScanRecords& r : records) {
    in_scan.insert(in_scan.end(), r.in_scan.begin(), r.in_scan.end());
    walls.insert(walls.end(), r.walls.begin(), r.walls.end());
    glass.insert(glass.end(), r.glass.begin(), r.glass.end());
    r.in_scan = {};
    r.walls = {};
    r.glass = {};
    if (r.aligned) {
      ++result.aligned_scans;
      shifts.push_back(r.shift_m);
      turns.push_back(r.turn_deg);
    }
  }
  result.median_alignment_m = detail::median(shifts);
  result.median_alignment_deg = detail::median(turns);
  SensorProfile& p = result.profile;
  p.wall_beams = walls.size();
  p.glass_beams = glass.size();
  p.max_range = scans.front().max_range;
  fitBeamModel(walls, o, p, result.warnings);
  result.range_sigma_em_m = p.range_sigma_m.value;
  {
    std::vector<double> ranges;
    for (const WallBeam& b : walls) ranges.push_back(b.e);
    p.typical_range_m = detail::median(ranges);
  }
  // Noise that grows with range, from the readings the EM called hits (against the walls) or from
  // neighbouring readings within scans (no map in it).
  if (o.sigma_source == SigmaSource::Walls && p.range_sigma_m.fitted) {
    // Gated at 3 sigma, first of the pooled fit, then of the fit at each beam's range: a pooled
    // gate would cut the far readings' spread and hide the growth it is looking for. The bins'
    // median deviations are unbiased for Gaussian noise well inside the gate.
    SensorProfile fit = p;
    detail::RangeNoiseFit f;
    for (int round = 0; round < 4; ++round) {
      std::vector<detail::RangeResidual> hits;
      for (const WallBeam& b : walls)
        if (b.fit_sigma && b.z < b.z_max && std::abs(b.z - b.e) < 3.0 * rangeSigmaAt(fit, b.e))
          hits.push_back({b.e, b.z - b.e});
      f = detail::fitRangeNoise(hits, 1.0);
      if (!f.ok || !f.rel_fitted) break;
      fit.range_sigma_m.value = f.sigma0;
      fit.range_sigma_rel.value = f.rel;
    }
    if (f.ok && f.rel_fitted) {
      p.range_sigma_m = {f.sigma0, f.sigma0_se, true};
      p.range_sigma_rel = {f.rel, f.rel_se, true};
    }
  }
  const detail::RangeNoiseFit local =
      o.sigma_source == SigmaSource::Prior ? detail::RangeNoiseFit{} : inScanFit(in_scan);
  if (o.sigma_source == SigmaSource::Prior) {
    result.range_sigma_local_m = rangeSigmaAt(o.prior, p.typical_range_m);
    p.range_sigma_m = o.prior.range_sigma_m;
    p.range_sigma_rel = o.prior.range_sigma_rel;
    p.typical_range_m = o.prior.typical_range_m;
  } else if (local.ok) {
    result.range_sigma_local_m =
        rangeSigmaAt(SensorProfile{.range_sigma_m = {local.sigma0}, .range_sigma_rel = {local.rel}}, p.typical_range_m);
    if (o.sigma_source == SigmaSource::Local) {
      // The noise, and the range it is typical at, from the scans alone (inScanNoise).
      p.range_sigma_m = {local.sigma0, local.sigma0_se, true};
      p.range_sigma_rel = {local.rel, local.rel_se, local.rel_fitted};
      p.typical_range_m = medianReturnRange(scans);
    }
  } else if (o.sigma_source == SigmaSource::Local) {
    result.warnings.push_back("too few neighbouring returns for the in-scan noise estimate: sigma from the walls");
  }

  // Glass: match each reading to a mode, then fit the lobes.
  // The gate follows the noise at the reading's range.
  auto gateOf = [&](const GlassBeam& b) {
    return std::max(o.min_gate_m, o.gate_sigmas * rangeSigmaAt(p, b.z < b.d_g + 50.f ? b.z : b.d_g));
  };
  const std::vector<bool> transient = transientPanes(glass, map, o, gateOf, result);
  std::vector<std::pair<float, bool>> direct_obs, mirror_obs;
  std::vector<double> offsets;
  for (const GlassBeam& b : glass) {
    if (transient[static_cast<std::size_t>(b.segment)]) continue;
    const double gate = gateOf(b);
    const double wide = gate + 0.10;  // the continued ray also carries an unknown offset
    // A reading short of the pane never reached it (a person, clutter): it says nothing of glass.
    if (b.z < b.d_g - gate) continue;
    const bool is_direct = std::abs(b.z - b.d_g) < gate;
    const bool near_mirror = std::isfinite(b.e_mirror) && std::abs(b.z - b.e_mirror) < gate;
    const bool near_through = std::isfinite(b.e_through) && std::abs(b.z - b.e_through) < wide;
    const bool direct_clear = std::abs(b.e_through - b.d_g) > 2 * wide && std::abs(b.e_mirror - b.d_g) > 2 * gate;
    if (direct_clear) direct_obs.emplace_back(b.theta_deg, is_direct);
    if (is_direct) continue;
    const bool mirror_clear = std::isfinite(b.e_mirror) && std::abs(b.e_mirror - b.e_through) > 2 * wide;
    if (mirror_clear) mirror_obs.emplace_back(b.theta_deg, near_mirror);
    if (near_through && b.panes == 1 && !near_mirror) offsets.push_back(b.z - b.e_through);
  }
  result.refracted_beams = offsets.size();
  {
    const int bins = static_cast<int>(std::ceil(90.0 / o.chart_bin_deg));
    result.bins.resize(static_cast<std::size_t>(bins));
    for (int b = 0; b < bins; ++b) {
      result.bins[static_cast<std::size_t>(b)].theta_lo = b * o.chart_bin_deg;
      result.bins[static_cast<std::size_t>(b)].theta_hi = std::min(90.0, (b + 1) * o.chart_bin_deg);
    }
    auto bin_of = [&](float theta) {
      return static_cast<std::size_t>(std::clamp(static_cast<int>(theta / o.chart_bin_deg), 0, bins - 1));
    };
    for (const auto& [theta, y] : direct_obs) {
      GlassAngleBin& a = result.bins[bin_of(theta)];
      ++a.beams;
      a.direct += y ? 1 : 0;
    }
    for (const auto& [theta, y] : mirror_obs) {
      GlassAngleBin& a = result.bins[bin_of(theta)];
      ++a.mirror_beams;
      a.reflected += y ? 1 : 0;
    }
  }
  if (direct_obs.size() >= o.min_glass_beams) {
    fitDirect(binBernoulli(direct_obs, 0.25), p);
    if (p.direct_sigma_deg.se > 0.5 * p.direct_sigma_deg.value || p.direct_sigma_deg.se == 0)
      result.warnings.push_back("the direct-return lobe is poorly determined (too few beams near normal incidence)");
  } else {
    result.warnings.push_back("only " + std::to_string(direct_obs.size()) +
                              " beams on glass with a clear direct mode: the glass lobe keeps its prior values");
  }
  const auto reflections = static_cast<std::size_t>(
      std::count_if(mirror_obs.begin(), mirror_obs.end(), [](const auto& obs) { return obs.second; }));
  if (mirror_obs.size() >= o.min_glass_beams / 2 && reflections < 20) {
    result.warnings.push_back("only " + std::to_string(reflections) +
                              " reflected returns seen: the reflection rate keeps its prior value");
  } else if (mirror_obs.size() >= o.min_glass_beams / 2) {
    fitMirror(binBernoulli(mirror_obs, 0.5), p);
  } else {
    result.warnings.push_back("only " + std::to_string(mirror_obs.size()) +
                              " beams on glass with a clear mirrored path: the reflection rate keeps its prior value");
  }
  if (offsets.size() >= 100) {
    const double m = detail::median(offsets);
    std::vector<double> dev;
    for (double x : offsets) dev.push_back(std::abs(x - m));
    const double mad = 1.4826 * detail::median(dev);
    p.glass_offset_m = {m, 1.2533 * mad / std::sqrt(static_cast<double>(offsets.size())), true};
  }
  return result;
}

bool inScanNoise(const LaserLog& log, const CalibrationOptions& o, SensorProfile& profile) {
  if (log.scanCount() == 0) return false;
  const std::vector<LaserScan> scans = pickScans(log, o.max_scans);
  std::vector<std::vector<detail::RangeResidual>> per_scan(scans.size());
  tbb::parallel_for(std::size_t{0}, scans.size(),
                    [&](std::size_t k) { detail::inScanResiduals(scans[k], per_scan[k]); });
  std::vector<detail::RangeResidual> in_scan;
  for (const auto& r : per_scan) in_scan.insert(in_scan.end(), r.begin(), r.end());
  const detail::RangeNoiseFit local = inScanFit(in_scan);
  if (!local.ok) return false;
  profile.range_sigma_m = {local.sigma0, local.sigma0_se, true};
  profile.range_sigma_rel = {local.rel, local.rel_se, local.rel_fitted};
  profile.typical_range_m = medianReturnRange(scans);
  return true;
}

}  // namespace glassmap::sensor
