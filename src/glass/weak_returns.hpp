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
  /// beams passed (at least min_through, at most max_hit_ratio of them returned) and that lie more
  /// than max(wall_clearance, 3 sigma(r)) from every occupied cell of `evidence`.
  WeakReturns(const LaserLog& log, const grid::BeamOptions& beams, const SparsePaneOptions& options,
              const CellEvidence& evidence);

  const std::vector<WeakReturn>& returns() const { return returns_; }
  /// Returns of 1-degree normal bin b.
  const std::vector<std::size_t>& bin(int b) const { return bins_[static_cast<std::size_t>(b)]; }
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
  std::vector<std::size_t> by_cell_;
  std::vector<double> cells_per_bin_;
  double observed_ = 1.0;
};

}  // namespace glassmap::glass::sparse
