#include "glassmap/eval/trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "glassmap/core/error.hpp"

namespace glassmap::eval {

TrajectoryErrors evaluateTrajectory(const std::vector<StampedPose>& truth_in, const std::vector<StampedPose>& estimate,
                                    const TrajectoryEvalOptions& options) {
  std::vector<StampedPose> truth = truth_in;
  std::stable_sort(truth.begin(), truth.end(),
                   [](const StampedPose& a, const StampedPose& b) { return a.timestamp < b.timestamp; });
  TrajectoryErrors r;
  r.good_error = options.good_error;
  for (const StampedPose& e : estimate) {
    const auto it = std::lower_bound(truth.begin(), truth.end(), e.timestamp,
                                     [](const StampedPose& p, double t) { return p.timestamp < t; });
    const StampedPose* best = nullptr;
    if (it != truth.end()) best = &*it;
    if (it != truth.begin() &&
        (!best || std::abs((it - 1)->timestamp - e.timestamp) < std::abs(best->timestamp - e.timestamp)))
      best = &*(it - 1);
    if (!best || std::abs(best->timestamp - e.timestamp) > options.max_time_diff) {
      ++r.unmatched;
      continue;
    }
    r.times.push_back(e.timestamp);
    r.position_errors.push_back((e.pose.t - best->pose.t).norm());
    r.heading_errors_deg.push_back(std::abs(rad2deg(angleDiff(e.pose.theta, best->pose.theta))));
  }
  r.matched = r.position_errors.size();
  if (r.matched == 0)
    throw Error("no estimate matches a ground-truth pose within " + std::to_string(options.max_time_diff) +
                " s: are the trajectories of the same run?");
  const auto n = static_cast<double>(r.matched);
  const std::vector<double>& e = r.position_errors;
  double sq = 0;
  for (double v : e) sq += v * v;
  r.rmse = std::sqrt(sq / n);
  r.mean = std::accumulate(e.begin(), e.end(), 0.0) / n;
  double var = 0;
  for (double v : e) var += (v - r.mean) * (v - r.mean);
  r.std = std::sqrt(var / n);  // population std, as evo
  r.min = *std::min_element(e.begin(), e.end());
  r.max = *std::max_element(e.begin(), e.end());
  std::vector<double> sorted = e;
  std::sort(sorted.begin(), sorted.end());
  r.median = r.matched % 2 ? sorted[r.matched / 2] : 0.5 * (sorted[r.matched / 2 - 1] + sorted[r.matched / 2]);
  r.heading_mean_deg = std::accumulate(r.heading_errors_deg.begin(), r.heading_errors_deg.end(), 0.0) / n;
  r.heading_max_deg = *std::max_element(r.heading_errors_deg.begin(), r.heading_errors_deg.end());
  // Fraction of time: each matched estimate stands for the interval to the next one (the last for
  // the mean interval); with a single estimate it is 0 or 1.
  double good = 0, total = 0;
  for (std::size_t i = 0; i < r.matched; ++i) {
    double dt = 1.0;
    if (r.matched > 1) {
      dt = i + 1 < r.matched ? r.times[i + 1] - r.times[i] : (r.times.back() - r.times.front()) / (n - 1.0);
    }
    dt = std::max(dt, 0.0);
    total += dt;
    if (e[i] < options.good_error) good += dt;
  }
  r.fraction_under =
      total > 0
          ? good / total
          : static_cast<double>(std::count_if(e.begin(), e.end(), [&](double v) { return v < options.good_error; })) /
                n;
  return r;
}

}  // namespace glassmap::eval
