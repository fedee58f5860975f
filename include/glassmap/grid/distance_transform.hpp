#pragma once
/// The exact Euclidean distance transform of a raster (Felzenszwalb & Huttenlocher 2012).

#include <cstdint>
#include <vector>

namespace glassmap::grid {

/// For every cell of a width x height raster (row-major), the distance [cells] to the nearest cell
/// where `source` is nonzero; +inf when there is none.
std::vector<float> distanceTransform(int width, int height, const std::vector<std::uint8_t>& source);

}  // namespace glassmap::grid
