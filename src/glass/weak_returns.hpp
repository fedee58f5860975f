#pragma once
/// The weak returns of a log (glass/sparse_panes.hpp): returns from cells most beams pass, away
/// from walls, each with the direction it came along, and the indexes the line search reads.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "glassmap/glass/evidence.hpp"
#include "glassmap/glass/sparse_panes.hpp"
#include "glassmap/grid/scan_integration.hpp"

namespace glassmap::glass::sparse {

inline constexpr int kAngleBins = 180;  ///< 1-degree bins of a normal angle over [0, 180)

/// An angle modulo pi, in [0, pi).
inline double wrapPi(double a) { return a - kPi * std::floor(a / kPi); }

/// Difference of two normal angles in [0, pi), modulo pi: in [-pi/2, pi/2].
inline double angleDiff(double a, double b) {
  const double d = a - b;
  return d > 0.5 * kPi ? d - kPi : (d < -0.5 * kPi ? d + kPi : d);
}

/// 1-degree bin of a normal angle in [0, pi).
inline int angleBinOf(double normal) {
  return std::clamp(static_cast<int>(normal * kAngleBins / kPi), 0, kAngleBins - 1);
}

/// A bin index modulo kAngleBins (bins wrap at 180 degrees).
inline int wrapBin(int b) { return (b % kAngleBins + kAngleBins) % kAngleBins; }

/// Glass cells of `label` in the (2 r + 1)^2 block around (x, y).
int glassInBlock(const grid::GridGeometry& g, const std::vector<std::uint8_t>& label, int x, int y, int r);

/// The laser's range noise at range r under the search's options: hypot(range_sigma, range_sigma_rel r) [m].
inline double rangeSigma(const SparsePaneOptions& o, double r) {
  return std::hypot(o.range_sigma, o.range_sigma_rel * r);
}

/// The parameter t in [0, 1] of segment a -> b where it enters the first occupied cell of `label`
/// (over grid g), or 1 when it meets none: how far a beam without an echo is known to have gone (a
/// wall's dropouts stop at the wall).
double clearUntil(const grid::GridGeometry& g, const std::vector<std::uint8_t>& label, const Vec2& a, const Vec2& b);

/// A return from a cell most beams pass, and the direction it came along (its pane's normal).
struct WeakReturn {
  Vec2 at;             ///< the reading [m]
  Vec2 from;           ///< the laser [m]
  double normal;       ///< beam direction modulo pi, in [0, pi)
  std::uint32_t cell;  ///< linear index of the reading's cell
};

/// The weak returns of a log and their indexes by angle bin and by cell.
class WeakReturns {
 public:
  /// Collects the returned beams (within the range noise sigma(r) of the options) whose cell most
  /// beams passed (at least min_through, at most max_hit_ratio of them returned; beams without an
  /// echo pass the cells before the first occupied cell they meet) and that lie more
  /// than max(wall_clearance, 3 sigma(r)) from every occupied cell of `evidence`.
  WeakReturns(const LaserLog& log, const grid::BeamOptions& beams, const SparsePaneOptions& options,
              const CellEvidence& evidence);

  const std::vector<WeakReturn>& returns() const { return returns_; }
  /// Returns of 1-degree normal bin b.
  const std::vector<std::size_t>& bin(int b) const { return bins_[static_cast<std::size_t>(b)]; }
  /// Calls fn(i) for the returns of the bins within `span` of the bin of `angle` that may lie within
  /// `tol` of the line n(angle) . p = rho: every such return, and some others (the caller tests).
  /// Each bin's returns are sorted by their offset along the bin's normal, which differs from the
  /// line's by at most |n - n_bin| times their largest distance from the centre.
  template <class Fn>
  void forNearLine(double angle, double rho, int span, double tol, Fn&& fn) const;
  /// True when at least `share` of the returns of `cell` came within `tol` [rad] of `normal`.
  bool specific(std::uint32_t cell, double normal, double tol, double share) const;
  /// True when some return of `cell` came within `tol` [rad] of `normal`.
  bool compatible(std::uint32_t cell, double normal, double tol) const;
  /// Share of the observed cells holding a return within `pad` bins of `normal`'s bin.
  double background(double normal, int pad) const;

 private:
  template <class Fn>
  void forCell(std::uint32_t cell, Fn&& fn) const;
  std::vector<WeakReturn> returns_;
  std::vector<std::vector<std::size_t>> bins_;
  struct Keyed {
    double key;     // offset from centre_ along the bin's normal [m]
    std::size_t i;  // the return
  };
  std::vector<std::vector<Keyed>> by_offset_;  // per bin, by key
  Vec2 centre_ = Vec2::Zero();
  double radius_ = 0.0;  // largest distance of a return from centre_ [m]
  std::vector<std::size_t> by_cell_;
  std::vector<double> cells_per_bin_;
  double observed_ = 1.0;
};

template <class Fn>
void WeakReturns::forNearLine(double angle, double rho, int span, double tol, Fn&& fn) const {
  const Vec2 n(std::cos(angle), std::sin(angle));
  const double rho_c = rho - n.dot(centre_);
  const int centre = angleBinOf(angle);
  for (int d = -span; d <= span; ++d) {
    const int b = wrapBin(centre + d);
    const std::vector<Keyed>& keyed = by_offset_[static_cast<std::size_t>(b)];
    if (keyed.empty()) continue;
    const double theta = (b + 0.5) * kPi / kAngleBins;
    const Vec2 nb(std::cos(theta), std::sin(theta));
    // The bin's normal, or its opposite, whichever is nearer the line's.
    const double s = n.dot(nb) >= 0.0 ? 1.0 : -1.0;
    const double slack = (n - s * nb).norm() * radius_ + 1e-6 * (1.0 + radius_ + std::abs(rho_c));
    double lo = rho_c - tol - slack, hi = rho_c + tol + slack;
    if (s < 0.0) {
      const double flipped_lo = -hi;
      hi = -lo;
      lo = flipped_lo;
    }
    auto it = std::lower_bound(keyed.begin(), keyed.end(), lo, [](const Keyed& k, double v) { return k.key < v; });
    for (; it != keyed.end() && it->key <= hi; ++it) fn(it->i);
  }
}

}  // namespace glassmap::glass::sparse
