#pragma once
/// The label grid of a glass-mapping result, so that `glassmap map` can vectorise in memory:
///   vector::vectorize(vector::toLabelGrid(result.evidence), options)

#include "glassmap/glass/evidence.hpp"
#include "glassmap/vector/label_grid.hpp"

namespace glassmap::vector {

/// Codes from the labels (glass/labels.hpp labelToCode); evidence per cell = posterior of its label,
/// exp(-cost), for candidate cells and 1 for the others (no beam ended there: certain).
LabelGrid toLabelGrid(const glass::CellEvidence& evidence);

}  // namespace glassmap::vector
