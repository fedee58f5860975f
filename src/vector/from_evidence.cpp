#include "glassmap/vector/from_evidence.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "glassmap/glass/labels.hpp"

namespace glassmap::vector {

LabelGrid toLabelGrid(const glass::CellEvidence& e) {
  LabelGrid g;
  g.width = e.geometry.width;
  g.height = e.geometry.height;
  g.resolution = e.geometry.resolution;
  g.origin = e.geometry.origin;
  g.angle_bin_deg = 180.0 / e.bins;
  g.codes.resize(e.label.size());
  for (std::size_t i = 0; i < e.label.size(); ++i) g.codes[i] = glass::labelToCode(e.label[i]);
  g.evidence.assign(e.label.size(), 1.0f);
  for (std::size_t k = 0; k < e.cells.size(); ++k) {
    const int label = e.label[e.cells[k]];
    if (label == glass::kUnknown || label >= e.num_labels) continue;
    g.evidence[e.cells[k]] = std::exp(-e.costs(k)[label]);
  }
  g.validate();
  return g;
}

std::size_t pruneUnfittedGlass(glass::CellEvidence& e, const VectorMap& floorplan, double tolerance) {
  const grid::GridGeometry& g = e.geometry;
  // Cells whose centre lies within the tolerance of some glass segment.
  std::vector<std::uint8_t> near(e.label.size(), 0);
  const int reach = static_cast<int>(std::ceil(tolerance / g.resolution)) + 1;
  for (const MapSegment& s : floorplan.segments) {
    if (s.material != Material::Glass) continue;
    const Vec2 lo = s.a.cwiseMin(s.b) - Vec2::Constant(tolerance);
    const Vec2 hi = s.a.cwiseMax(s.b) + Vec2::Constant(tolerance);
    const grid::CellIndex c0 = g.cellAt(lo), c1 = g.cellAt(hi);
    for (int y = std::max(0, c0.y - reach); y <= std::min(g.height - 1, c1.y + reach); ++y)
      for (int x = std::max(0, c0.x - reach); x <= std::min(g.width - 1, c1.x + reach); ++x) {
        const Vec2 p = g.origin + (Vec2(x, y) + Vec2(0.5, 0.5)) * g.resolution;
        const Vec2 ab = s.b - s.a;
        const double len2 = ab.squaredNorm();
        const double t = len2 > 0 ? std::clamp((p - s.a).dot(ab) / len2, 0.0, 1.0) : 0.0;
        if ((p - (s.a + t * ab)).norm() <= tolerance) near[g.index(x, y)] = 1;
      }
  }
  std::size_t changed = 0;
  for (std::size_t i = 0; i < e.label.size(); ++i) {
    const int label = e.label[i];
    if (!glass::isGlass(label) || near[i]) continue;
    int best = glass::kEmpty;
    const std::int64_t k = e.candidate(static_cast<std::uint32_t>(i));
    if (k >= 0) {
      const float* c = e.costs(static_cast<std::size_t>(k));
      best = c[glass::kOccupied] < c[glass::kEmpty] ? glass::kOccupied : glass::kEmpty;
    }
    e.label[i] = static_cast<std::uint8_t>(best);
    ++changed;
  }
  return changed;
}

}  // namespace glassmap::vector
