#include "glassmap/vector/from_evidence.hpp"

#include <cmath>

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

}  // namespace glassmap::vector
