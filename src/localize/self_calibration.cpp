#include "glassmap/localize/self_calibration.hpp"

#include <algorithm>

#include "glassmap/sensor/calibrate.hpp"

namespace glassmap::localize {

SensorProfile profileFromParams(const sensor::SensorParams& p) {
  SensorProfile out;
  out.range_sigma_m = {p.sigma_hit, 0.0, false};
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

void SelfCalibrator::add(std::size_t index, const Pose2& estimate, double step_m) {
  scans_.push_back(index);
  poses_.push_back(estimate);
  trusted_m_ += step_m;
}

bool SelfCalibrator::due() const { return opt_.enabled && !scans_.empty() && trusted_m_ >= next_fit_m_; }

SelfCalibrationFit SelfCalibrator::fit(const LaserLog& log, const sensor::SensorParams& current) {
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
  return fit;
}

}  // namespace glassmap::localize
