#include "glassmap/eval/segments.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <vector>

#include "glassmap/core/angles.hpp"
#include "glassmap/core/error.hpp"

namespace glassmap::eval {
namespace {

struct Indexed {
  const MapSegment* s;
  std::size_t index;        // in its map
  Eigen::AlignedBox2d box;  // grown by the tolerance
};

std::vector<Indexed> ofMaterial(const VectorMap& map, Material m, double grow) {
  std::vector<Indexed> out;
  for (std::size_t i = 0; i < map.segments.size(); ++i) {
    const MapSegment& s = map.segments[i];
    if (s.material != m) continue;
    Eigen::AlignedBox2d b;
    b.extend(s.a);
    b.extend(s.b);
    b.min() -= Vec2::Constant(grow);
    b.max() += Vec2::Constant(grow);
    out.push_back({&s, i, b});
  }
  return out;
}

// Nearest segment of `others` within tol of p, or -1.
std::ptrdiff_t nearestWithin(const Vec2& p, const std::vector<Indexed>& others, double tol) {
  std::ptrdiff_t best = -1;
  double best_d = tol;
  for (std::size_t k = 0; k < others.size(); ++k) {
    const Eigen::AlignedBox2d& b = others[k].box;
    if (p.x() < b.min().x() || p.y() < b.min().y() || p.x() > b.max().x() || p.y() > b.max().y()) continue;
    const double d = others[k].s->distanceTo(p);
    if (d <= best_d) best_d = d, best = static_cast<std::ptrdiff_t>(k);
  }
  return best;
}

// Undirected angle between two segments [deg] in [0, 90].
double angleBetweenDeg(const MapSegment& a, const MapSegment& b) {
  const double ta = std::atan2(a.b.y() - a.a.y(), a.b.x() - a.a.x());
  const double tb = std::atan2(b.b.y() - b.a.y(), b.b.x() - b.a.x());
  return rad2deg(std::abs(std::remainder(ta - tb, kPi)));
}

// Calls f(sample point, sample length) at the midpoints of n equal pieces of s, n = ceil(len / step).
template <typename F>
void forSamples(const MapSegment& s, double step, F&& f) {
  const double len = s.length();
  if (len <= 0) return;
  const int n = std::max(1, static_cast<int>(std::ceil(len / step)));
  for (int i = 0; i < n; ++i) f(s.a + ((i + 0.5) / n) * (s.b - s.a), len / n);
}

void finish(MaterialScores& m) {
  m.precision = m.pred_length > 0 ? m.correct_length / m.pred_length : 1.0;
  m.recall = m.truth_length > 0 ? m.found_length / m.truth_length : 1.0;
  m.f1 = m.precision + m.recall > 0 ? 2 * m.precision * m.recall / (m.precision + m.recall) : 0.0;
}

}  // namespace

SegmentEvalResult evaluateSegments(const VectorMap& truth, const VectorMap& pred, const SegmentEvalOptions& options) {
  if (!(options.tolerance >= 0)) throw Error("tolerance must be non-negative", {}, 0, "tolerance");
  if (!(options.sample_step > 0)) throw Error("sample step must be positive", {}, 0, "sample_step");
  const double tol = options.tolerance;
  SegmentEvalResult r;
  r.tolerance = tol;
  double angle_sum = 0, angle_weight = 0;
  for (const Material m : {Material::Glass, Material::Wall}) {
    MaterialScores& sc = m == Material::Glass ? r.glass : r.wall;
    const auto t = ofMaterial(truth, m, tol), p = ofMaterial(pred, m, tol);
    sc.truth_segments = t.size();
    sc.pred_segments = p.size();
    // Predicted samples: correct when near true segments of the material.
    for (const Indexed& ps : p) {
      double run = 0;  // current stretch of unmatched glass [m]
      forSamples(*ps.s, options.sample_step, [&](const Vec2& q, double w) {
        sc.pred_length += w;
        const std::ptrdiff_t k = nearestWithin(q, t, tol);
        if (k < 0) {
          run += w;
          if (m == Material::Glass) r.longest_false_glass = std::max(r.longest_false_glass, run);
          return;
        }
        run = 0;
        sc.correct_length += w;
        if (m == Material::Glass) {
          angle_sum += w * angleBetweenDeg(*ps.s, *t[static_cast<std::size_t>(k)].s);
          angle_weight += w;
        }
      });
    }
    // True samples: found when near predicted segments of the material.
    for (const Indexed& ts : t) {
      std::set<std::size_t> matched;
      forSamples(*ts.s, options.sample_step, [&](const Vec2& q, double w) {
        sc.truth_length += w;
        const std::ptrdiff_t k = nearestWithin(q, p, tol);
        if (k < 0) return;
        sc.found_length += w;
        matched.insert(static_cast<std::size_t>(k));
      });
      if (m == Material::Glass && !matched.empty()) {
        ++r.panes_found;
        r.segments_per_found_pane += static_cast<double>(matched.size());
      }
    }
    finish(sc);
  }
  r.glass_angle_error_deg = angle_weight > 0 ? angle_sum / angle_weight : 0.0;
  r.oversegmentation = r.glass.truth_segments > 0
                           ? static_cast<double>(r.glass.pred_segments) / static_cast<double>(r.glass.truth_segments)
                           : 0.0;
  if (r.panes_found > 0) r.segments_per_found_pane /= static_cast<double>(r.panes_found);
  return r;
}

}  // namespace glassmap::eval
