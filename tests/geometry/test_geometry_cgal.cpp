#include <gtest/gtest.h>

#include "glassmap/geometry/cgal.hpp"

using namespace glassmap;

TEST(Cgal, SegmentRoundTripsExactly) {
  MapSegment s;
  s.a = Vec2(1.25, -3.5);
  s.b = Vec2(0.1, 7.3e3);
  s.material = Material::Glass;
  s.thickness = 0.012;
  const CgalSegment2 c = toCgal(s);
  EXPECT_EQ(c.source(), CgalPoint2(1.25, -3.5));
  EXPECT_EQ(c.target(), CgalPoint2(0.1, 7.3e3));
  const MapSegment back = fromCgal(c, s.material, s.thickness);
  EXPECT_EQ(back.a, s.a);
  EXPECT_EQ(back.b, s.b);
  EXPECT_EQ(back.material, Material::Glass);
  EXPECT_EQ(back.thickness, 0.012);
}

TEST(Cgal, ConvertedSegmentsWorkWithCgalPredicates) {
  MapSegment s1, s2;
  s1.a = Vec2(0, 0);
  s1.b = Vec2(2, 2);
  s2.a = Vec2(0, 2);
  s2.b = Vec2(2, 0);
  EXPECT_TRUE(CGAL::do_intersect(toCgal(s1), toCgal(s2)));
  s2.a = Vec2(3, 0);
  s2.b = Vec2(4, 1);  // parallel to s1, offset
  EXPECT_FALSE(CGAL::do_intersect(toCgal(s1), toCgal(s2)));
}
