#include "glassmap/localize/localizer.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>

#include "glassmap/core/atomic_file.hpp"
#include "glassmap/core/error.hpp"

namespace glassmap::localize {
namespace {

// Odometry pose at time t from ODOM records (linear interpolation, clamped at the ends).
Pose2 odometryAt(const std::vector<StampedPose>& odom, double t) {
  const auto it =
      std::lower_bound(odom.begin(), odom.end(), t, [](const StampedPose& p, double v) { return p.timestamp < v; });
  if (it == odom.begin()) return odom.front().pose;
  if (it == odom.end()) return odom.back().pose;
  const StampedPose& b = *it;
  const StampedPose& a = *(it - 1);
  const double span = b.timestamp - a.timestamp;
  return Pose2::interpolate(a.pose, b.pose, span > 0 ? (t - a.timestamp) / span : 0.0);
}

}  // namespace

LocalizeResult localizeLog(const LaserLog& log, sensor::SensorModel& model, const LocalizeOptions& options) {
  LocalizeResult result;
  result.scans = log.scans.size();
  if (log.scans.empty()) return result;
  for (const LaserScan& s : log.scans)
    if (!s.has_odom && log.odometry.empty())
      throw Error("the log has scans without odometry and no ODOM records: localization needs odometry");

  const auto clock = std::chrono::steady_clock::now;
  const auto t_start = clock();
  double update_seconds = 0.0;
  double particle_sum = 0.0;

  ParticleFilter filter(model, options.filter);
  SelfCalibrator calibrator(model.map(), options.self_calibration);
  const auto laserOdom = [&](const LaserScan& s) {
    return (s.has_odom ? s.odom_pose : odometryAt(log.odometry, s.timestamp)) * options.T_base_laser;
  };

  Pose2 odom_at_update = laserOdom(log.scans.front());
  std::vector<std::uint8_t> sure;  // per scan: the filter converged (one tight mode holds the mass)
  sure.reserve(log.scans.size());
  std::vector<double> travelled;  // per scan: odometry distance from the first scan [m]
  travelled.reserve(log.scans.size());
  Pose2 odom_before = odom_at_update;
  Pose2 est_at_update;
  result.trajectory.reserve(log.scans.size());
  for (std::size_t k = 0; k < log.scans.size(); ++k) {
    const LaserScan& scan = log.scans[k];
    const Pose2 odom = laserOdom(scan);
    const OdometryDelta delta = odometryDelta(odom_at_update, odom);
    const double turned = std::abs(angleDiff(odom.theta, odom_at_update.theta));
    const bool first = k == 0;
    const bool updated = first || std::abs(delta.trans) >= options.update_min_trans || turned >= options.update_min_rot;
    if (updated) {
      const auto t0 = clock();
      if (first) {
        if (options.init)
          filter.initialize(*options.init, options.init_sigma_xy, options.init_sigma_theta);
        else
          filter.initializeGlobal();
      } else {
        filter.predict(delta);
      }
      const sensor::BeamSet beams = sensor::makeBeamSet(scan, options.beams);
      // The scans are compared with each other whole (beams already holds them all when it is not
      // a subset).
      const bool subset = options.beams > 0 && static_cast<std::size_t>(options.beams) < scan.ranges.size();
      const sensor::BeamSet whole = subset ? sensor::makeBeamSet(scan, 0) : sensor::BeamSet{};
      particle_sum += static_cast<double>(filter.size());
      if (filter.correct(beams, subset ? &whole : nullptr)) ++result.resamplings;
      result.injected += filter.lastInjected();
      ++result.updates;
      odom_at_update = odom;
      est_at_update = filter.estimate();
      // Self-calibration: scans where the filter is sure of its pose (one tight mode, no wall
      // contradicting it) feed refits of the sensor model.
      if (options.self_calibration.enabled && filter.converged() &&
          filter.spread() < options.self_calibration.trust_spread &&
          filter.contradiction() <= options.filter.contradiction_share) {
        calibrator.add(k, est_at_update, filter.spread(), odom, std::abs(delta.trans), result.updates);
        if (calibrator.due()) {
          SelfCalibrationFit fit = calibrator.fit(log, model.params(), filter.motionNoise());
          if (fit.applied) model.setParams(fit.params);
          if (fit.motion_windows > 0) filter.setMotionNoise(fit.noise);
          result.calibrations.push_back(std::move(fit));
        }
      }
      update_seconds += std::chrono::duration<double>(clock() - t0).count();
      result.trajectory.push_back({scan.timestamp, est_at_update, 0.0, 0.0});
    } else {
      // Between updates the estimate follows the odometry.
      result.trajectory.push_back({scan.timestamp, est_at_update * odom_at_update.between(odom), 0.0, 0.0});
    }
    result.spread.push_back(filter.spread());
    result.particles.push_back(filter.size());
    result.corrected.push_back(updated ? 1 : 0);
    result.relocalized.push_back(filter.relocalizations());
    // Between updates the filter's state stands as it was at the last one.
    sure.push_back(filter.converged() ? 1 : 0);
    travelled.push_back((travelled.empty() ? 0.0 : travelled.back()) + (odom.t - odom_before.t).norm());
    odom_before = odom;
  }
  result.relocalizations = filter.relocalizations();
  result.probes = filter.probes();
  result.breaks = filter.breaks();
  result.final_params = model.params();
  // Converged for good: one tight hypothesis holding all but a negligible mass (a spread cloud,
  // or rival places still alive, is not) from some scan to the end. Never a confident answer
  // while the cloud is still split.
  const std::size_t n = result.spread.size();
  // After a jump of the estimate to another place, that place has only the scans since its probe
  // began for it: it is no answer until the robot has travelled as far again as a global start
  // needs (converged_after_jump).
  double jumped_at = 0.0;  // odometry distance of the last jump [m]
  for (std::size_t k = 0; k < n; ++k) {
    if (k > 0 && result.relocalized[k] != result.relocalized[k - 1]) jumped_at = travelled[k];
    if (result.relocalized[k] > 0 && travelled[k] - jumped_at < options.converged_after_jump) sure[k] = 0;
  }
  result.settled.assign(n, 0);
  for (std::size_t k = n; k-- > 0;) {
    if (!sure[k] || (k + 1 < n && !result.settled[k + 1])) break;
    result.settled[k] = 1;
  }
  // ... over enough travel: odometry distance from the first settled scan to the last.
  std::size_t first_settled = n;
  for (std::size_t k = 0; k < n; ++k)
    if (result.settled[k]) {
      first_settled = k;
      break;
    }
  const double settled_travel = first_settled < n ? travelled[n - 1] - travelled[first_settled] : 0.0;
  result.converged = n > 0 && result.settled[n - 1] && settled_travel >= options.converged_min_travel;
  if (!result.converged) std::fill(result.settled.begin(), result.settled.end(), std::uint8_t{0});
  for (std::size_t k = 0; k < n && result.converged; ++k)
    if (result.settled[k]) {
      result.converged_at = result.trajectory[k].timestamp - log.scans.front().timestamp;
      break;
    }
  result.seconds = std::chrono::duration<double>(clock() - t_start).count();
  result.seconds_per_update = result.updates ? update_seconds / static_cast<double>(result.updates) : 0.0;
  result.mean_particles = result.updates ? particle_sum / static_cast<double>(result.updates) : 0.0;
  result.log_duration = log.scans.back().timestamp - log.scans.front().timestamp;
  return result;
}

void writeSpreadCsv(const std::filesystem::path& path, const LocalizeResult& result) {
  const std::size_t n = result.trajectory.size();
  if (result.spread.size() != n || result.particles.size() != n || result.corrected.size() != n ||
      result.relocalized.size() != n || (!result.settled.empty() && result.settled.size() != n))
    throw Error("the per-scan filter state does not match the trajectory", path.string());
  writeAtomically(path, [&](const std::filesystem::path& tmp) {
    std::ofstream out(tmp);
    out << "t,spread_m,particles,corrected,relocalizations,converged\n";
    char line[128];
    for (std::size_t k = 0; k < n; ++k) {
      std::snprintf(line, sizeof line, "%.6f,%.6g,%zu,%d,%zu,%d\n", result.trajectory[k].timestamp, result.spread[k],
                    result.particles[k], static_cast<int>(result.corrected[k]), result.relocalized[k],
                    result.settled.empty() ? 0 : static_cast<int>(result.settled[k]));
      out << line;
    }
    if (!out) throw Error("cannot write", path.string());
  });
}

}  // namespace glassmap::localize
