// Ray consistency of a floorplan with a log (see consistency.hpp).
#include "glassmap/eval/consistency.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "glassmap/core/error.hpp"
#include "glassmap/geometry/ray_caster.hpp"

namespace glassmap::eval {
namespace {

struct Tally {
  std::size_t scans = 0, returns = 0, explained = 0, at_glass = 0, short_of_plan = 0, through_wall = 0, near = 0;
  Tally& operator+=(const Tally& o) {
    near += o.near;
    scans += o.scans;
    returns += o.returns;
    explained += o.explained;
    at_glass += o.at_glass;
    short_of_plan += o.short_of_plan;
    through_wall += o.through_wall;
    return *this;
  }
};

// Walks one beam: surfaces up to the reading plus the tolerance, crossing glass.
void scoreBeam(const RayCaster& caster, const Vec2& origin, const Vec2& dir, double reading, double tol, Tally& t) {
  ++t.returns;
  double travelled = 0.0;
  Vec2 from = origin;
  std::int32_t skip = -1;
  // A beam crosses at most a few panes; the bound only guards against a degenerate plan.
  for (int surfaces = 0; surfaces < 64; ++surfaces) {
    const RayHit hit = caster.castSurface(from, dir, reading + tol - travelled, skip);
    if (!hit.hit()) {
      ++t.short_of_plan;  // nothing within reach: the reading ends in empty space
      return;
    }
    const double at = travelled + hit.range;
    if (std::abs(at - reading) <= tol) {
      ++t.explained;
      if (hit.material == Material::Glass) ++t.at_glass;
      return;
    }
    // The surface lies before the reading (by more than the tolerance).
    if (hit.material != Material::Glass) {
      ++t.through_wall;
      return;
    }
    travelled = at;
    from = origin + travelled * dir;
    skip = hit.segment;
  }
  ++t.through_wall;
}

// Segments by the buckets of a uniform grid they pass near: which segments lie within a distance
// of a point.
class NearIndex {
 public:
  NearIndex(const VectorMap& plan, double reach) : plan_(plan), reach_(reach) {
    const Eigen::AlignedBox2d box = plan.bounds();
    if (box.isEmpty()) return;
    lo_ = box.min() - Vec2::Constant(2 * reach);
    const Vec2 size = box.sizes() + Vec2::Constant(4 * reach);
    cell_ = std::max({0.5, 4 * reach, std::sqrt(size.x() * size.y() / std::max<double>(1, plan.segments.size()))});
    nx_ = static_cast<int>(size.x() / cell_) + 1;
    ny_ = static_cast<int>(size.y() / cell_) + 1;
    buckets_.resize(static_cast<std::size_t>(nx_) * ny_);
    for (std::size_t i = 0; i < plan.segments.size(); ++i) {
      const MapSegment& s = plan.segments[i];
      const Vec2 a = s.a.cwiseMin(s.b) - Vec2::Constant(reach), b = s.a.cwiseMax(s.b) + Vec2::Constant(reach);
      for (int y = cellOf(a.y() - lo_.y(), ny_); y <= cellOf(b.y() - lo_.y(), ny_); ++y)
        for (int x = cellOf(a.x() - lo_.x(), nx_); x <= cellOf(b.x() - lo_.x(), nx_); ++x)
          buckets_[static_cast<std::size_t>(y) * nx_ + x].push_back(static_cast<std::uint32_t>(i));
    }
  }
  bool near(const Vec2& p) const {
    if (buckets_.empty()) return false;
    const double fx = (p.x() - lo_.x()) / cell_, fy = (p.y() - lo_.y()) / cell_;
    if (!(fx >= 0 && fy >= 0 && fx < nx_ && fy < ny_)) return false;
    for (const std::uint32_t i : buckets_[static_cast<std::size_t>(fy) * nx_ + static_cast<int>(fx)])
      if (plan_.segments[i].distanceTo(p) <= reach_) return true;
    return false;
  }

 private:
  int cellOf(double v, int n) const { return std::clamp(static_cast<int>(v / cell_), 0, n - 1); }
  const VectorMap& plan_;
  double reach_;
  Vec2 lo_ = Vec2::Zero();
  double cell_ = 1.0;
  int nx_ = 0, ny_ = 0;
  std::vector<std::vector<std::uint32_t>> buckets_;
};

}  // namespace

ConsistencyResult rayConsistency(const LaserLog& log, const VectorMap& plan, const ConsistencyOptions& options) {
  if (!(options.tolerance > 0.0) || !(options.max_range > options.min_range) || options.min_range < 0.0)
    throw Error("ray consistency: tolerance must be > 0 and 0 <= min_range < max_range (got tolerance " +
                std::to_string(options.tolerance) + ", ranges " + std::to_string(options.min_range) + " .. " +
                std::to_string(options.max_range) + ")");
  ConsistencyResult r;
  r.tolerance = options.tolerance;
  r.max_range = options.max_range;
  for (const MapSegment& s : plan.segments) {
    ++r.segments;
    if (s.material == Material::Glass) {
      ++r.glass_segments;
      r.glass_length += s.length();
    } else {
      ++r.wall_segments;
      r.wall_length += s.length();
    }
  }
  // Scans spread evenly over the log when a maximum is given.
  std::vector<std::size_t> chosen;
  const std::size_t n = log.scans.size();
  const std::size_t take = options.max_scans > 0 ? std::min(options.max_scans, n) : n;
  chosen.reserve(take);
  for (std::size_t k = 0; k < take; ++k) chosen.push_back(take == n ? k : k * n / take);

  const RayCaster caster(plan);
  const NearIndex near(plan, options.tolerance);
  const Tally total = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, chosen.size(), 16), Tally{},
      [&](const tbb::blocked_range<std::size_t>& range, Tally t) {
        for (std::size_t k = range.begin(); k != range.end(); ++k) {
          const LaserScan& scan = log.scans[chosen[k]];
          ++t.scans;
          for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
            if (!scan.isReturn(i)) continue;
            const double reading = scan.ranges[i];
            if (reading < options.min_range || reading > options.max_range) continue;
            const double a = scan.laser_pose.theta + scan.beamAngle(i);
            const Vec2 dir(std::cos(a), std::sin(a));
            scoreBeam(caster, scan.laser_pose.t, dir, reading, options.tolerance, t);
            t.near += near.near(scan.laser_pose.t + reading * dir);
          }
        }
        return t;
      },
      [](Tally a, const Tally& b) { return a += b; });
  r.scans = total.scans;
  r.returns = total.returns;
  r.explained = total.explained;
  r.at_glass = total.at_glass;
  r.short_of_plan = total.short_of_plan;
  r.through_wall = total.through_wall;
  r.explained_share = r.returns > 0 ? static_cast<double>(r.explained) / static_cast<double>(r.returns) : 0.0;
  r.near_segment = total.near;
  r.near_share = r.returns > 0 ? static_cast<double>(r.near_segment) / static_cast<double>(r.returns) : 0.0;
  return r;
}

}  // namespace glassmap::eval
