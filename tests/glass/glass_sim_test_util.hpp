#pragma once
// Shared by the glass tests that simulate their input: a log classified by the direct classifier
// alone (the steps after it are what the tests exercise), and map drawing helpers.

#include <initializer_list>

#include "glassmap/glass/mapping.hpp"
#include "glassmap/sim/simulator.hpp"

namespace glassmap::glass::testing {

/// A simulated log and its direct-classifier evidence.
struct Classified {
  LaserLog log;
  MappingOptions options;
  MappingResult mapped;
};

inline Classified simulateAndClassify(const sim::Scene& scene) {
  Classified c;
  c.log = sim::simulate(scene).log;
  c.options.method = Method::Direct;
  c.mapped = mapLog(c.log, c.options);
  return c;
}

/// Adds the polyline through `points` to `map` as segments of `material`.
inline void addPolyline(VectorMap& map, std::initializer_list<Vec2> points, Material material = Material::Wall) {
  const Vec2* prev = nullptr;
  for (const Vec2& p : points) {
    if (prev) map.add(*prev, p, material);
    prev = &p;
  }
}

/// Adds the four walls of the axis-aligned box with corners lo and hi.
inline void addBox(VectorMap& map, const Vec2& lo, const Vec2& hi) {
  addPolyline(map, {lo, Vec2(hi.x(), lo.y()), hi, Vec2(lo.x(), hi.y()), lo});
}

}  // namespace glassmap::glass::testing
