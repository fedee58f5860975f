#pragma once
/// Test helper of the sensor tests: a map segment in one call.

#include "glassmap/geometry/vector_map.hpp"

namespace glassmap::sensor::test {

inline MapSegment seg(Vec2 a, Vec2 b, Material m = Material::Wall, double thickness = 0.1) {
  MapSegment s;
  s.a = a;
  s.b = b;
  s.material = m;
  s.thickness = thickness;
  return s;
}

}  // namespace glassmap::sensor::test
