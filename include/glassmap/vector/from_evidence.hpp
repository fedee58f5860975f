#pragma once
/// The label grid of a glass-mapping result, so that `glassmap map` can vectorise in memory:
///   vector::vectorize(vector::toLabelGrid(result.evidence), options)

#include <cstddef>

#include "glassmap/geometry/vector_map.hpp"
#include "glassmap/glass/evidence.hpp"
#include "glassmap/vector/label_grid.hpp"

namespace glassmap::vector {

/// Codes from the labels (core/labels.hpp labelToCode); evidence per cell = posterior of its label,
/// exp(-cost), for candidate cells and 1 for the others (no beam ended there: certain).
LabelGrid toLabelGrid(const glass::CellEvidence& evidence);

/// Panes are straight and at least a few decimetres long; a person walking by, seen from one side,
/// leaves arcs of cells that each look like glass facing the robot, which the fit drops. This puts
/// the cells back in line with the floorplan: a glass cell farther than `tolerance` [m] from every
/// glass segment of `floorplan` takes its best non-glass label (EMP or OCC by cost; EMP without
/// costs). Returns the number of cells relabelled.
std::size_t pruneUnfittedGlass(glass::CellEvidence& evidence, const VectorMap& floorplan, double tolerance = 0.10);

/// The other half of putting the cells in line with the floorplan: a faint pane draws one cell in
/// three or four, and the gaps between them are free cells a planner would drive through. Every
/// cell a glass segment of `floorplan` passes through that is labelled empty or unknown becomes
/// glass with the segment's direction (walls stay walls). Returns the number of cells relabelled.
std::size_t fillFittedGlass(glass::CellEvidence& evidence, const VectorMap& floorplan);

}  // namespace glassmap::vector
