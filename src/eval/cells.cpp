#include "glassmap/eval/cells.hpp"

#include <cmath>
#include <limits>

#include "glassmap/core/error.hpp"
#include "glassmap/core/labels.hpp"
#include "glassmap/grid/traversal.hpp"

namespace glassmap::eval {
namespace {

DetectionScores scores(double tp_pred, double predicted, double tp_truth, double truth) {
  DetectionScores s;
  s.precision = predicted > 0 ? tp_pred / predicted : 0.0;
  s.recall = truth > 0 ? tp_truth / truth : 0.0;
  s.f1 = s.precision + s.recall > 0 ? 2.0 * s.precision * s.recall / (s.precision + s.recall) : 0.0;
  return s;
}

}  // namespace

std::vector<float> rasteriseGlass(const VectorMap& truth, const grid::GridGeometry& g, std::size_t* outside) {
  std::vector<float> normal(g.cells(), std::numeric_limits<float>::quiet_NaN());
  std::size_t out = 0;
  for (const MapSegment& s : truth.segments) {
    if (s.material != Material::Glass || s.length() <= 0.0) continue;
    const Vec2 d = s.b - s.a;
    const float n = static_cast<float>(wrapHalfTurn(std::atan2(d.y(), d.x()) + kPi / 2));
    grid::traverse(g, s.a, s.b, [&](int x, int y, double, bool) { normal[g.index(x, y)] = n; });
    // Cells of the segment beyond the grid: count them by walking a grid grown to cover it.
    Eigen::AlignedBox2d box;
    box.extend(s.a);
    box.extend(s.b);
    grid::GridGeometry big = g;
    const int pad_lo_x = std::max(0, static_cast<int>(std::ceil((g.origin.x() - box.min().x()) / g.resolution)) + 1);
    const int pad_lo_y = std::max(0, static_cast<int>(std::ceil((g.origin.y() - box.min().y()) / g.resolution)) + 1);
    big.origin = g.origin - Vec2(pad_lo_x * g.resolution, pad_lo_y * g.resolution);
    big.width = g.width + pad_lo_x +
                std::max(0, static_cast<int>(std::ceil((box.max().x() - g.maxCorner().x()) / g.resolution)) + 1);
    big.height = g.height + pad_lo_y +
                 std::max(0, static_cast<int>(std::ceil((box.max().y() - g.maxCorner().y()) / g.resolution)) + 1);
    grid::traverse(big, s.a, s.b, [&](int x, int y, double, bool) {
      if (!g.contains(x - pad_lo_x, y - pad_lo_y)) ++out;
    });
  }
  if (outside) *outside = out;
  return normal;
}

CellEvalResult evaluateCells(const VectorMap& truth, const grid::GridGeometry& g,
                             const std::vector<std::uint8_t>& labels, int bins, const CellEvalOptions& o) {
  if (labels.size() != g.cells()) throw Error("label grid size does not match its geometry");
  if (o.tolerance_cells < 0) throw Error("tolerance must be >= 0", {}, 0, "tolerance_cells");
  CellEvalResult r;
  r.tolerance_cells = o.tolerance_cells;
  const std::vector<float> normal = rasteriseGlass(truth, g, &r.truth_outside);
  const int tol = o.tolerance_cells;
  const double bin_rad = kPi / bins;
  auto isPredicted = [&](int x, int y) { return isGlass(labels[g.index(x, y)]); };
  std::size_t exact_pred = 0;  // predicted cells on a true cell
  double angle_sum = 0.0;
  for (int y = 0; y < g.height; ++y) {
    for (int x = 0; x < g.width; ++x) {
      const std::size_t i = g.index(x, y);
      const bool is_true = !std::isnan(normal[i]);
      const bool is_pred = isGlass(labels[i]);
      if (is_true) {
        ++r.ground_truth;
        if (is_pred) {
          ++r.exact_found;
        } else {
          bool near = false;
          for (int dy = -tol; dy <= tol && !near; ++dy) {
            for (int dx = -tol; dx <= tol && !near; ++dx) {
              near = g.contains(x + dx, y + dy) && isPredicted(x + dx, y + dy);
            }
          }
          r.found_displaced += near;
        }
      }
      if (is_pred) {
        ++r.predicted;
        exact_pred += is_true;
        // Nearest true cell within tolerance (Euclidean in cells).
        int best_d2 = std::numeric_limits<int>::max();
        float best_n = 0.0f;
        for (int dy = -tol; dy <= tol; ++dy) {
          for (int dx = -tol; dx <= tol; ++dx) {
            if (!g.contains(x + dx, y + dy)) continue;
            const float n = normal[g.index(x + dx, y + dy)];
            if (std::isnan(n) || dx * dx + dy * dy >= best_d2) continue;
            best_d2 = dx * dx + dy * dy;
            best_n = n;
          }
        }
        if (best_d2 == std::numeric_limits<int>::max()) {
          ++r.false_positives;
        } else {
          ++r.found;
          const double pred_n = glassBin(labels[i]) * bin_rad;
          angle_sum += std::abs(angleDiff(2.0 * pred_n, 2.0 * best_n)) / 2.0;  // modulo pi
          ++r.angle_cells;
        }
      }
    }
  }
  r.ground_truth += r.truth_outside;
  r.not_found = r.ground_truth - r.exact_found - r.found_displaced;
  const double gt = static_cast<double>(r.ground_truth), pred = static_cast<double>(r.predicted);
  r.exact = scores(static_cast<double>(exact_pred), pred, static_cast<double>(r.exact_found), gt);
  r.tolerant = scores(static_cast<double>(r.found), pred, static_cast<double>(r.exact_found + r.found_displaced), gt);
  r.paper_recall = gt > 0 ? r.found / gt : 0.0;
  r.paper_precision = gt > 0 ? r.exact_found / gt : 0.0;
  r.mean_angle_error_deg = r.angle_cells ? rad2deg(angle_sum / static_cast<double>(r.angle_cells)) : 0.0;
  return r;
}

}  // namespace glassmap::eval
