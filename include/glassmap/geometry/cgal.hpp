#pragma once
/// Header-only conversions between MapSegment and CGAL's Epick Segment_2, for the stages that
/// run CGAL algorithms (vector/). Include it only where CGAL is needed: it is costly to compile.

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include "glassmap/geometry/vector_map.hpp"

namespace glassmap {

/// The kernel of the vector map: exact predicates, inexact (double) constructions.
using CgalKernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using CgalPoint2 = CgalKernel::Point_2;
using CgalSegment2 = CgalKernel::Segment_2;

/// Vec2 -> CGAL point [m].
inline CgalPoint2 toCgal(const Vec2& p) { return {p.x(), p.y()}; }
/// CGAL point -> Vec2 [m].
inline Vec2 fromCgal(const CgalPoint2& p) { return {CGAL::to_double(p.x()), CGAL::to_double(p.y())}; }
/// The segment's endpoints a -> b as a CGAL segment (material and thickness are not carried).
inline CgalSegment2 toCgal(const MapSegment& s) { return {toCgal(s.a), toCgal(s.b)}; }
/// A CGAL segment as a MapSegment of the given material and thickness [m].
inline MapSegment fromCgal(const CgalSegment2& s, Material material = Material::Wall, double thickness = 0.1) {
  MapSegment m;
  m.a = fromCgal(s.source());
  m.b = fromCgal(s.target());
  m.material = material;
  m.thickness = thickness;
  return m;
}

}  // namespace glassmap
