#pragma once
/// Test helper: reads a GeoJSON FeatureCollection of LineStrings (material, thickness
/// properties) into a VectorMap with nlohmann_json (the geometry module does not depend on io).

#include <string>

#include "glassmap/geometry/vector_map.hpp"

namespace glassmap::test {

/// Each consecutive coordinate pair of every LineString becomes one segment. Throws on error.
VectorMap readGeoJsonSegments(const std::string& path);

}  // namespace glassmap::test
