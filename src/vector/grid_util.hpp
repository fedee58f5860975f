#pragma once
// Private to vector/: raster tools the structure stage, the room segmentation and the test maps
// share: connected components, a cell walk along a ray, and a platform-independent random source
// (the Euclidean distance transform is grid/distance_transform.hpp).

#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include "glassmap/core/pose2.hpp"

namespace glassmap::vector::detail {

/// Connected components of the cells where `in` is true (4- or 8-connected), labelled 0..count-1;
/// cells outside the set hold -1. `sizes[k]` counts the cells of component k.
struct Components {
  std::vector<std::int32_t> label;
  std::vector<std::size_t> sizes;
  std::size_t count() const { return sizes.size(); }
};
Components connectedComponents(int width, int height, const std::vector<std::uint8_t>& in, bool eight = false);

/// Visits the cells a segment from p to q crosses (grid coordinates in cells, the grid's lower-left
/// corner at 0), in order, stopping when `visit(x, y)` returns false or the walk leaves the grid.
/// Amanatides–Woo. The cell containing q is visited last.
void walkCells(const Vec2& p, const Vec2& q, int width, int height, const std::function<bool(int, int)>& visit);

}  // namespace glassmap::vector::detail
