#include "glassmap/localize/self_calibration.hpp"

#include <algorithm>

#include "glassmap/sensor/calibrate.hpp"

namespace glassmap::localize {

SensorProfile profileFromParams(const sensor::SensorParams& p) {
  SensorProfile out;
  out.range_sigma_m = {p.sigma_hit, 0.0, false};
  out.range_sigma_rel = {p.sigma_hit_rel, 0.0, false};
  out.w_hit = {p.z_hit, 0.0, false};
  out.w_short = {p.z_short, 0.0, false};
  out.w_max = {p.z_max, 0.0, false};
  out.w_rand = {p.z_rand, 0.0, false};
  out.lambda_short = {p.lambda_short, 0.0, false};
  out.direct_peak = {p.direct_peak, 0.0, false};
  out.direct_sigma_deg = {p.direct_sigma_deg, 0.0, false};
  out.direct_floor = {p.direct_floor, 0.0, false};
  out.normal_lambda_per_deg = {p.lambda_normal, 0.0, false};
  out.normal_floor = {p.normal_floor, 0.0, false};
  out.glass_offset_m = {std::max(p.offset, 0.0), 0.0, false};
  out.max_range = p.max_range;
  out.source = "localize defaults";
  return out;
}

SelfCalibrator::SelfCalibrator(const VectorMap& map, SelfCalibrationOptions options)
    : map_(map), opt_(options), next_fit_m_(options.first_after_m) {}

void SelfCalibrator::add(std::size_t index, const Pose2& estimate, double spread, const Pose2& odometry, double step_m,
                         std::size_t update) {
  spread_.push_back(spread);
  scans_.push_back(index);
  poses_.push_back(estimate);
  odometry_.push_back(odometry);
  updates_.push_back(update);
  trusted_m_ += step_m;
  along_.push_back(trusted_m_);
}

std::size_t SelfCalibrator::fitMotion(OdometryNoise& noise) const {
  // Windows of consecutive trusted updates spanning about motion_window_m: the estimate's motion
  // against the odometry's, in the frame of the window's start.
  std::vector<double> along, heading;
  std::size_t i = 0;
  while (i + 1 < scans_.size()) {
    std::size_t j = i + 1;
    while (j < scans_.size() && updates_[j] == updates_[j - 1] + 1 && along_[j] - along_[i] < opt_.motion_window_m) ++j;
    if (j >= scans_.size() || updates_[j] != updates_[j - 1] + 1) {
      i = j;
      continue;
    }
    const double length = along_[j] - along_[i];
    if (length <= 3.0 * opt_.motion_window_m) {
      const Pose2 e = odometry_[i].between(odometry_[j]).inverse() * poses_[i].between(poses_[j]);
      // The estimates' own uncertainty (the clouds' spread along one axis) is not odometry error.
      const double own = 0.5 * (spread_[i] * spread_[i] + spread_[j] * spread_[j]);
      along.push_back((e.x() * e.x() - own) / length);
      heading.push_back(e.theta * e.theta / length);
    }
    i = j;
  }
  if (along.size() < opt_.min_windows) return 0;
  // The median of a squared normal is 0.455 of its variance; per metre of the window.
  auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  const OdometryNoise defaults;
  noise.walk_trans = std::max(defaults.walk_trans, median(along) / 0.455);
  noise.walk_heading = std::max(defaults.walk_heading, median(heading) / 0.455);
  return along.size();
}

bool SelfCalibrator::due() const { return opt_.enabled && !scans_.empty() && trusted_m_ >= next_fit_m_; }

SelfCalibrationFit SelfCalibrator::fit(const LaserLog& log, const sensor::SensorParams& current,
                                       const OdometryNoise& noise) {
  next_fit_m_ = std::max(trusted_m_, next_fit_m_) * std::max(opt_.growth, 1.01);
  // The trusted scans, evenly spread, at the filter's estimates.
  LaserLog sub;
  const std::size_t n = scans_.size(), want = std::min(n, std::max<std::size_t>(opt_.max_scans, 1));
  sub.scans.reserve(want);
  for (std::size_t k = 0; k < want; ++k) {
    const std::size_t i = k * n / want;
    LaserScan s = log.scans[scans_[i]];
    s.laser_pose = poses_[i];
    sub.scans.push_back(std::move(s));
  }
  sensor::CalibrationOptions co;
  co.max_scans = want;
  co.prior = profileFromParams(current);
  const sensor::CalibrationResult r = sensor::calibrate(sub, map_, co);

  SelfCalibrationFit fit;
  fit.time = log.scans[scans_.back()].timestamp - log.scans.front().timestamp;
  fit.scans = want;
  fit.trusted_m = trusted_m_;
  fit.params = sensor::paramsFromProfile(r.profile, current, opt_.min_sigma_hit);
  fit.params.sigma_hit = std::min(fit.params.sigma_hit, opt_.max_sigma_hit);
  const double sum = fit.params.z_hit + fit.params.z_short + fit.params.z_max + fit.params.z_rand;
  fit.applied = sum > 0 && fit.params.z_hit / sum >= opt_.min_hit_weight;
  fit.noise = noise;
  if (opt_.motion && fit.applied) fit.motion_windows = fitMotion(fit.noise);
  return fit;
}

}  // namespace glassmap::localize
