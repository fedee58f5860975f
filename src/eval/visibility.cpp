#include "glassmap/eval/visibility.hpp"

#include <algorithm>
#include <cmath>

#include "glassmap/core/angles.hpp"
#include "glassmap/geometry/ray_caster.hpp"

namespace glassmap::eval {
namespace {

// True if `p` (a point on segment `own`) is in line of sight of v: within its range and field of
// view, and no wall other than `own` crosses the line between them. Glass is passed through.
bool sees(const Viewpoint& v, const Vec2& p, std::int32_t own, const VectorMap& map, const RayCaster& caster) {
  const Vec2 delta = p - v.pose.t;
  const double dist = delta.norm();
  if (dist > v.max_range || dist < 1e-6) return false;
  const double bearing = wrapAngle(std::atan2(delta.y(), delta.x()) - v.pose.theta - v.start_angle);
  const double within = bearing < 0 ? bearing + 2.0 * kPi : bearing;  // [0, 2 pi) from the first beam
  if (v.span < 2.0 * kPi - 1e-9 && within > v.span) return false;
  const Vec2 dir = delta / dist;
  constexpr double kSlack = 0.01;  // stop short of p: its own segment must not count as a blocker
  Vec2 origin = v.pose.t;
  double left = dist - kSlack;
  std::int32_t skip = -1;
  for (int panes = 0; panes < 64 && left > 0; ++panes) {
    const RayHit hit = caster.cast(origin, dir, left, skip);
    if (!hit.hit() || hit.segment == own) return true;
    if (map.segments[static_cast<std::size_t>(hit.segment)].material != Material::Glass) return false;
    origin += hit.range * dir;
    left -= hit.range;
    skip = hit.segment;
  }
  return left <= 0;
}

}  // namespace

std::vector<Viewpoint> viewpointsOfLog(const LaserLog& log, double spacing, double range_cap) {
  std::vector<Viewpoint> out;
  for (const LaserScan& scan : log.scans) {
    if (scan.ranges.empty()) continue;
    const Pose2& pose = scan.laser_pose;
    if (!out.empty()) {
      const Pose2& last = out.back().pose;
      if ((pose.t - last.t).norm() < spacing && std::abs(angleDiff(pose.theta, last.theta)) < deg2rad(10.0)) continue;
    }
    Viewpoint v;
    v.pose = pose;
    v.start_angle = scan.start_angle;
    v.span = std::abs(scan.fieldOfView());
    if (scan.angular_step < 0) v.start_angle += scan.fieldOfView();  // beams listed clockwise
    v.max_range = scan.max_range > 0 ? std::min(scan.max_range, range_cap) : range_cap;
    out.push_back(v);
  }
  return out;
}

VectorMap visiblePart(const VectorMap& truth, const std::vector<Viewpoint>& viewpoints, double step) {
  VectorMap out;
  out.name = truth.name;
  if (truth.segments.empty()) return out;
  const RayCaster caster(truth);
  std::size_t hint = 0;  // the viewpoint that saw the last sample: neighbours tend to share it
  for (std::size_t k = 0; k < truth.segments.size(); ++k) {
    const MapSegment& s = truth.segments[k];
    const double len = s.length();
    const int n = std::max(1, static_cast<int>(std::ceil(len / step)));
    auto visible = [&](const Vec2& p) {
      if (viewpoints.empty()) return false;
      if (sees(viewpoints[hint], p, static_cast<std::int32_t>(k), truth, caster)) return true;
      for (std::size_t i = 0; i < viewpoints.size(); ++i) {
        if (i == hint) continue;
        if (sees(viewpoints[i], p, static_cast<std::int32_t>(k), truth, caster)) {
          hint = i;
          return true;
        }
      }
      return false;
    };
    int run_start = -1;
    auto close = [&](int end) {  // samples run_start .. end-1 were visible
      if (run_start < 0) return;
      MapSegment piece = s;
      const double t0 = std::max(0.0, (run_start + 0.0) / n), t1 = std::min(1.0, (end + 0.0) / n);
      piece.a = s.a + t0 * (s.b - s.a);
      piece.b = s.a + t1 * (s.b - s.a);
      if (piece.length() > 0) out.segments.push_back(piece);
      run_start = -1;
    };
    for (int i = 0; i < n; ++i) {
      const Vec2 p = s.a + ((i + 0.5) / n) * (s.b - s.a);
      if (visible(p)) {
        if (run_start < 0) run_start = i;
      } else {
        close(i);
      }
    }
    close(n);
  }
  return out;
}

}  // namespace glassmap::eval
