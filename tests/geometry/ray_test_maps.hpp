#pragma once
/// Test helper: segment maps that collect the ray caster's awkward cases.

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "glassmap/core/angles.hpp"

#include "glassmap/geometry/vector_map.hpp"

namespace glassmap::test {

inline MapSegment seg(double ax, double ay, double bx, double by, Material m = Material::Wall, double thickness = 0.1) {
  MapSegment s;
  s.a = Vec2(ax, ay);
  s.b = Vec2(bx, by);
  s.material = m;
  s.thickness = thickness;
  return s;
}

// A map that collects the awkward cases: axis-aligned and diagonal segments on a coarse lattice
// (so many share endpoints, touch in T-junctions, overlap collinearly and lie on cell borders),
// tiny, huge and zero-length segments, plus free random ones.
inline VectorMap randomMap(std::mt19937& rng, int count) {
  std::uniform_real_distribution<double> u(-20.0, 20.0);
  std::uniform_int_distribution<int> lattice(-10, 10);
  std::uniform_int_distribution<int> kind(0, 9);
  VectorMap map;
  for (int i = 0; i < count; ++i) {
    const int k = kind(rng);
    const Material m = (i % 3 == 0) ? Material::Glass : Material::Wall;
    if (k <= 1) {  // axis-aligned on the lattice
      const double x = lattice(rng), y = lattice(rng);
      const double len = 1 + (lattice(rng) + 10) % 6;
      map.segments.push_back(k == 0 ? seg(x, y, x + len, y, m) : seg(x, y, x, y + len, m));
    } else if (k == 2) {  // diagonal on the lattice
      const double x = lattice(rng), y = lattice(rng), len = 1 + (lattice(rng) + 10) % 4;
      map.segments.push_back(seg(x, y, x + len, y + ((i % 2) ? len : -len), m));
    } else if (k == 3) {  // tiny
      const double x = u(rng), y = u(rng);
      map.segments.push_back(seg(x, y, x + 1e-6 * u(rng), y + 1e-6 * u(rng), m));
    } else if (k == 4 && i % 7 == 0) {  // huge
      map.segments.push_back(seg(u(rng) * 50, u(rng) * 50, u(rng) * 50, u(rng) * 50, m));
    } else if (k == 5 && i % 5 == 0) {  // zero length
      const double x = lattice(rng), y = lattice(rng);
      map.segments.push_back(seg(x, y, x, y, m));
    } else if (k == 6 && !map.segments.empty()) {  // collinear continuation of another segment
      const MapSegment& o = map.segments[rng() % map.segments.size()];
      map.segments.push_back(seg(o.b.x(), o.b.y(), 2 * o.b.x() - o.a.x(), 2 * o.b.y() - o.a.y(), m));
    } else {
      map.segments.push_back(seg(u(rng), u(rng), u(rng), u(rng), m));
    }
  }
  return map;
}

/// One ray of a test: origin, unit direction, max range [m], segment to skip (-1 none).
struct RayCase {
  Vec2 origin, dir;
  double max_range;
  int skip;
};

/// Rays of every kind against `map`: origins mostly inside its bounds, some outside, some exactly
/// on a segment (sometimes skipping it) or an endpoint or a lattice point (cell borders);
/// directions random, axis-aligned, diagonal or aimed at an endpoint; max ranges from 1 mm to
/// infinity.
inline std::vector<RayCase> rayCases(const VectorMap& map, std::mt19937& rng, int rays) {
  const Eigen::AlignedBox2d box = map.bounds();
  const Vec2 size = box.max() - box.min();
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::uniform_real_distribution<double> angle(-kPi, kPi);
  const auto& segs = map.segments;
  const double extent = std::max(size.x(), size.y());
  std::vector<RayCase> out;
  for (int i = 0; i < rays; ++i) {
    const int kind = i % 8;
    Vec2 o(box.min().x() + (uni(rng) * 1.4 - 0.2) * size.x(), box.min().y() + (uni(rng) * 1.4 - 0.2) * size.y());
    int skip = -1;
    if (kind == 1 && !segs.empty()) {
      const auto id = static_cast<int>(rng() % segs.size());
      o = segs[id].a + uni(rng) * (segs[id].b - segs[id].a);
      if (i % 16 == 1) skip = id;
    } else if (kind == 2 && !segs.empty()) {
      o = segs[rng() % segs.size()].b;  // on an endpoint
    } else if (kind == 3) {
      o = Vec2(std::round(o.x()), std::round(o.y()));  // on the lattice, often on cell borders
    }
    Vec2 d(std::cos(angle(rng)), std::sin(angle(rng)));
    d.normalize();
    if (kind == 3 || kind == 4) {  // axis-aligned and diagonal
      const int q = static_cast<int>(rng() % 8);
      d = Vec2(std::cos(q * kPi / 4), std::sin(q * kPi / 4));
      if (q % 2 == 0) d = Vec2(std::round(d.x()), std::round(d.y()));
    } else if (kind == 5 && !segs.empty()) {  // aimed at an endpoint
      const MapSegment& s = segs[rng() % segs.size()];
      const Vec2 target = (rng() % 2) ? s.a : s.b;
      if ((target - o).norm() > 1e-9) d = (target - o).normalized();
    }
    double max_range = (0.05 + uni(rng)) * extent;
    if (i % 11 == 0) max_range = std::numeric_limits<double>::infinity();
    if (i % 13 == 0) max_range = 1e-3;
    out.push_back({o, d, max_range, skip});
  }
  return out;
}

}  // namespace glassmap::test
