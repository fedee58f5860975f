#pragma once
// Private to vector/: which boxes overlap, through CGAL::box_intersection_d (one translation unit
// compiles it). Boxes are closed: touching boxes overlap.

#include <cstddef>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

namespace glassmap::vector::detail {

/// Pairs (i, j), i < j, of boxes that overlap, sorted; empty boxes take no part.
std::vector<std::pair<std::size_t, std::size_t>> overlappingPairs(const std::vector<Eigen::AlignedBox2d>& boxes);

/// Pairs (point, box) with the point inside the box, sorted by point then box.
std::vector<std::pair<std::size_t, std::size_t>> pointsInBoxes(const std::vector<Eigen::Vector2d>& points,
                                                               const std::vector<Eigen::AlignedBox2d>& boxes);

}  // namespace glassmap::vector::detail
