#include "glassmap/vector/from_evidence.hpp"

#include <cmath>

#include "glassmap/core/labels.hpp"

namespace glassmap::vector {

LabelGrid toLabelGrid(const glass::CellEvidence& e) {
  LabelGrid g;
  g.width = e.geometry.width;
  g.height = e.geometry.height;
  g.resolution = e.geometry.resolution;
  g.origin = e.geometry.origin;
  g.angle_bin_deg = 180.0 / e.bins;
  g.codes.resize(e.label.size());
  for (std::size_t i = 0; i < e.label.size(); ++i) g.codes[i] = labelToCode(e.label[i]);
  g.evidence.assign(e.label.size(), 1.0f);
  for (std::size_t k = 0; k < e.cells.size(); ++k) {
    const int label = e.label[e.cells[k]];
    if (label == kUnknown || label >= e.num_labels) continue;
    g.evidence[e.cells[k]] = std::exp(-e.costs(k)[label]);
  }
  g.validate();
  return g;
}

namespace {

// The glass segments of `floorplan` drawn over the grid of e with their panes' directions (in e's
// angle bins): each a band as thick as the segment and at least `min_width` [m], or with `lines`
// only the cells its line passes through.
LabelGrid glassRaster(const glass::CellEvidence& e, const VectorMap& floorplan, double min_width, bool lines) {
  VectorMap panes;
  for (const MapSegment& s : floorplan.segments)
    if (s.material == Material::Glass) {
      panes.segments.push_back(s);
      if (lines) panes.segments.back().thickness = 0.0;
    }
  LabelGrid g = makeLabelGrid(e.geometry.width, e.geometry.height, e.geometry.resolution, e.geometry.origin);
  g.angle_bin_deg = 180.0 / e.bins;
  rasterize(g, panes, min_width);
  return g;
}

}  // namespace

std::size_t pruneUnfittedGlass(glass::CellEvidence& e, const VectorMap& floorplan, double tolerance) {
  // Cells within the tolerance of some glass segment: the glass segments as bands 2 * tolerance wide.
  const LabelGrid near = glassRaster(e, floorplan, 2.0 * tolerance, false);
  std::size_t changed = 0;
  for (std::size_t i = 0; i < e.label.size(); ++i) {
    const int label = e.label[i];
    if (!isGlass(label) || near.codes[i] != kCodeUnknown) continue;
    int best = kEmpty;
    const std::int64_t k = e.candidate(static_cast<std::uint32_t>(i));
    if (k >= 0) {
      const float* c = e.costs(static_cast<std::size_t>(k));
      best = c[kOccupied] < c[kEmpty] ? kOccupied : kEmpty;
    }
    e.label[i] = static_cast<std::uint8_t>(best);
    ++changed;
  }
  return changed;
}

std::size_t fillFittedGlass(glass::CellEvidence& e, const VectorMap& floorplan) {
  if (floorplan.count(Material::Glass) == 0) return 0;
  const LabelGrid on = glassRaster(e, floorplan, 0.0, true);
  std::size_t changed = 0;
  for (std::size_t i = 0; i < e.label.size(); ++i) {
    const int label = e.label[i];
    if (!isGlassCode(on.codes[i]) || (label != kEmpty && label != kUnknown)) continue;
    e.label[i] = static_cast<std::uint8_t>(codeToLabel(on.codes[i]));
    ++changed;
  }
  return changed;
}

}  // namespace glassmap::vector
