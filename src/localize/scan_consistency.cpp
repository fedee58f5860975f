#include "glassmap/localize/scan_consistency.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace glassmap::localize {
namespace {

// A scan's beams by bearing: what it saw free along each direction.
struct Polar {
  std::vector<double> angle;  // ascending [rad]
  std::vector<double> range;  // the reading; +inf for no return (says nothing) [m]
  double spacing = 0.0;       // median angle between neighbouring beams [rad]
};

Polar polarOf(const sensor::BeamSet& s) {
  std::vector<std::size_t> order(s.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return s.angles[a] < s.angles[b]; });
  Polar p;
  p.angle.reserve(order.size());
  p.range.reserve(order.size());
  for (std::size_t i : order) {
    p.angle.push_back(s.angles[i]);
    p.range.push_back(s.ranges[i] < s.max_range ? s.ranges[i] : std::numeric_limits<double>::infinity());
  }
  if (p.angle.size() > 1) {
    std::vector<double> gaps(p.angle.size() - 1);
    for (std::size_t i = 0; i + 1 < p.angle.size(); ++i) gaps[i] = p.angle[i + 1] - p.angle[i];
    std::nth_element(gaps.begin(), gaps.begin() + static_cast<std::ptrdiff_t>(gaps.size() / 2), gaps.end());
    p.spacing = gaps[gaps.size() / 2];
  }
  return p;
}

// The nearest return of `p` within `tol` of bearing `bearing`: how far it saw free there. NaN when
// no beam is that close in bearing (outside its field of view, or between sparse beams), +inf when
// the beams there returned nothing.
double freeAlong(const Polar& p, double bearing, double tol) {
  double nearest = std::numeric_limits<double>::quiet_NaN();
  for (const double shift : {0.0, -2.0 * kPi, 2.0 * kPi}) {
    const double b = bearing + shift;
    auto it = std::lower_bound(p.angle.begin(), p.angle.end(), b - tol);
    for (; it != p.angle.end() && *it <= b + tol; ++it) {
      const double r = p.range[static_cast<std::size_t>(it - p.angle.begin())];
      nearest = std::isnan(nearest) ? r : std::min(nearest, r);
    }
  }
  return nearest;
}

// Readings of `from` (at T_odom_from) inside the free space of `to` (at T_odom_to): adds to the
// counts of `r`.
void countInto(const sensor::BeamSet& from, const Pose2& T_odom_from, const Polar& to, const Pose2& T_odom_to,
               const ScanConsistencyOptions& o, ScanConsistencyResult& r) {
  const Pose2 T_to_from = T_odom_to.between(T_odom_from);
  for (std::size_t i = 0; i < from.size(); ++i) {
    if (!(from.ranges[i] < from.max_range)) continue;
    const Vec2 q = T_to_from * from.points[i];
    const double d = q.norm();
    // Between the beams of a sparse scan, the nearest one.
    const double free = freeAlong(to, std::atan2(q.y(), q.x()), std::max(o.bearing_tolerance, 0.5 * to.spacing));
    if (std::isnan(free) || !std::isfinite(free)) continue;
    ++r.compared;
    r.contradicted += d + o.margin + o.margin_per_m * d < free;
  }
}

}  // namespace

ScanConsistencyResult compareScans(const sensor::BeamSet& a, const Pose2& T_odom_a, const sensor::BeamSet& b,
                                   const Pose2& T_odom_b, const ScanConsistencyOptions& options) {
  ScanConsistencyResult r;
  countInto(b, T_odom_b, polarOf(a), T_odom_a, options, r);
  countInto(a, T_odom_a, polarOf(b), T_odom_b, options, r);
  if (r.compared >= std::max<std::size_t>(options.min_compared, 1)) {
    r.share = static_cast<double>(r.contradicted) / static_cast<double>(r.compared);
    r.broke = r.share > options.break_share;
  }
  return r;
}

ScanConsistencyResult ScanConsistency::add(const sensor::BeamSet& scan, const Pose2& T_odom_laser) {
  ScanConsistencyResult r;
  if (last_) r = compareScans(*last_, last_pose_, scan, T_odom_laser, opt_);
  last_ = scan;
  last_pose_ = T_odom_laser;
  return r;
}

}  // namespace glassmap::localize
