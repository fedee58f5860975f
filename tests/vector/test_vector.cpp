// Vectorisation on synthetic label grids: each test draws a known floorplan into a raster (plus
// noise), vectorises it and checks the segments against what was drawn.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "glassmap/core/angles.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/vector/vectorize.hpp"

namespace glassmap::vector {
namespace {

MapSegment seg(double ax, double ay, double bx, double by, Material m, double thickness) {
  MapSegment s;
  s.a = Vec2(ax, ay);
  s.b = Vec2(bx, by);
  s.material = m;
  s.thickness = thickness;
  return s;
}

LabelGrid gridWith(const std::vector<MapSegment>& segments, double w = 6.0, double h = 5.0) {
  LabelGrid g = makeLabelGrid(static_cast<int>(w / 0.05), static_cast<int>(h / 0.05), 0.05);
  std::fill(g.codes.begin(), g.codes.end(), kCodeEmpty);
  VectorMap map;
  map.segments = segments;
  rasterize(g, map);
  return g;
}

std::vector<MapSegment> ofMaterial(const VectorMap& map, Material m) {
  std::vector<MapSegment> out;
  for (const MapSegment& s : map.segments)
    if (s.material == m) out.push_back(s);
  return out;
}

// Undirected line direction difference [deg] in [0, 90].
double directionErrorDeg(const MapSegment& s, double expected_rad) {
  const double a = std::atan2(s.b.y() - s.a.y(), s.b.x() - s.a.x());
  return rad2deg(std::abs(std::remainder(a - expected_rad, kPi)));
}

// Endpoints match in either order within tol [m].
bool sameEnds(const MapSegment& s, const Vec2& a, const Vec2& b, double tol) {
  return ((s.a - a).norm() <= tol && (s.b - b).norm() <= tol) || ((s.a - b).norm() <= tol && (s.b - a).norm() <= tol);
}

void addSalt(LabelGrid& g, double density, std::uint32_t seed, bool glass) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::uniform_int_distribution<int> bin(0, 35);
  for (auto& c : g.codes)
    if (u(rng) < density) c = glass ? static_cast<std::uint8_t>(kCodeFirstGlass + bin(rng)) : kCodeOccupied;
}

TEST(LabelGrid, GlassCodesAndValidation) {
  EXPECT_EQ(glassCodeOf(0.0), 10);
  EXPECT_EQ(glassCodeOf(deg2rad(90.0)), 28);
  EXPECT_EQ(glassCodeOf(deg2rad(181.0)), 10);
  EXPECT_EQ(glassCodeOf(deg2rad(178.0)), 10);  // 180 deg is bin 0
  LabelGrid g = makeLabelGrid(4, 3, 0.05);
  EXPECT_NEAR(g.normalOf(28), kPi / 2, 1e-12);
  EXPECT_NO_THROW(g.validate());
  g.codes.pop_back();
  EXPECT_THROW(g.validate(), Error);
  g = makeLabelGrid(4, 3, 0.05);
  g.codes[0] = 10 + 36;  // past the last 5-degree bin
  EXPECT_THROW(g.validate(), Error);
  g = makeLabelGrid(4, 3, 0.0);
  EXPECT_THROW(g.validate(), Error);
}

TEST(Vectorize, EmptyGridGivesEmptyMap) {
  const LabelGrid g = gridWith({});
  const VectorizeResult r = vectorize(g);
  EXPECT_TRUE(r.map.segments.empty());
}

TEST(Vectorize, NoisyStraightPaneIsOneSegment) {
  LabelGrid g = gridWith({seg(1.0, 2.0, 4.5, 2.0, Material::Glass, 0.01)});
  addSalt(g, 0.01, 7, true);
  const VectorizeResult r = vectorize(g);
  const auto glass = ofMaterial(r.map, Material::Glass);
  ASSERT_EQ(glass.size(), 1u);
  EXPECT_LT(directionErrorDeg(glass[0], 0.0), 0.5);
  EXPECT_TRUE(sameEnds(glass[0], Vec2(1.0, 2.0), Vec2(4.5, 2.0), 0.08))
      << glass[0].a.transpose() << " -> " << glass[0].b.transpose();
  EXPECT_NEAR(glass[0].pane_angle, kPi / 2, deg2rad(0.5));
  EXPECT_GE(glass[0].support, 60u);
  EXPECT_TRUE(ofMaterial(r.map, Material::Wall).empty());  // salt is glass only
}

TEST(Vectorize, AngledPaneStaysAngled) {
  // An axis-aligned room plus a pane at 17 degrees: regularisation must not rotate the pane.
  const double a = deg2rad(17.0);
  LabelGrid g = gridWith({seg(0.5, 0.5, 5.5, 0.5, Material::Wall, 0.15), seg(0.5, 0.5, 0.5, 4.5, Material::Wall, 0.15),
                          seg(1.5, 2.0, 1.5 + 3.0 * std::cos(a), 2.0 + 3.0 * std::sin(a), Material::Glass, 0.01)});
  const VectorizeResult r = vectorize(g);
  const auto glass = ofMaterial(r.map, Material::Glass);
  ASSERT_EQ(glass.size(), 1u);
  EXPECT_LT(directionErrorDeg(glass[0], a), 1.0);
  EXPECT_NEAR(glass[0].length(), 3.0, 0.1);
}

TEST(Vectorize, SlightlyOffAxisWallIsSnappedToTheAxes) {
  const double a = deg2rad(1.5);
  LabelGrid g = gridWith({seg(0.5, 0.5, 5.5, 0.5, Material::Wall, 0.15), seg(0.5, 0.5, 0.5, 4.5, Material::Wall, 0.15),
                          seg(1.5, 2.5, 1.5 + 3.5 * std::cos(a), 2.5 + 3.5 * std::sin(a), Material::Wall, 0.1)});
  const VectorizeResult r = vectorize(g);
  const auto walls = ofMaterial(r.map, Material::Wall);
  ASSERT_EQ(walls.size(), 3u);
  const double axis = std::atan2(walls[0].b.y() - walls[0].a.y(), walls[0].b.x() - walls[0].a.x());
  for (const MapSegment& w : walls)
    EXPECT_LT(std::min(directionErrorDeg(w, axis), directionErrorDeg(w, axis + kPi / 2)), 1e-6);
  EXPECT_LT(std::min(directionErrorDeg(walls[0], 0.0), directionErrorDeg(walls[0], kPi / 2)), 0.2);
  EXPECT_GE(r.stats.regularized, 1u);
}

TEST(Vectorize, LOfThickWallsIsTwoSegmentsMeetingAtTheCorner) {
  const LabelGrid g =
      gridWith({seg(1.0, 1.0, 5.0, 1.0, Material::Wall, 0.2), seg(1.0, 1.0, 1.0, 4.0, Material::Wall, 0.2)});
  const VectorizeResult r = vectorize(g);
  const auto walls = ofMaterial(r.map, Material::Wall);
  ASSERT_EQ(walls.size(), 2u);
  int horizontal = 0, vertical = 0;
  for (const MapSegment& w : walls) {
    if (directionErrorDeg(w, 0.0) < 1.0) {
      ++horizontal;
      EXPECT_TRUE(sameEnds(w, Vec2(1.0, 1.0), Vec2(5.0, 1.0), 0.15)) << w.a.transpose() << " -> " << w.b.transpose();
    } else if (directionErrorDeg(w, kPi / 2) < 1.0) {
      ++vertical;
      EXPECT_TRUE(sameEnds(w, Vec2(1.0, 1.0), Vec2(1.0, 4.0), 0.15)) << w.a.transpose() << " -> " << w.b.transpose();
    }
    EXPECT_NEAR(w.thickness, 0.2, 0.08);
  }
  EXPECT_EQ(horizontal, 1);
  EXPECT_EQ(vertical, 1);
}

TEST(Vectorize, TwoFacesOfAWallBecomeOneCentreLine) {
  // A 0.25 m wall seen from both sides: two bands of occupied cells, unknown inside.
  LabelGrid g =
      gridWith({seg(0.5, 2.0, 5.5, 2.0, Material::Wall, 0.05), seg(0.5, 2.25, 5.5, 2.25, Material::Wall, 0.05)});
  for (int x = 0; x < g.width; ++x)
    for (int y = 0; y < g.height; ++y) {
      const Vec2 c = g.center(x, y);
      if (c.y() > 2.05 && c.y() < 2.2) g.codes[static_cast<std::size_t>(y) * g.width + x] = kCodeUnknown;
    }
  const VectorizeResult r = vectorize(g);
  const auto walls = ofMaterial(r.map, Material::Wall);
  ASSERT_EQ(walls.size(), 1u);
  EXPECT_NEAR(0.5 * (walls[0].a.y() + walls[0].b.y()), 2.125, 0.03);
  EXPECT_NEAR(walls[0].thickness, 0.3, 0.06);
  EXPECT_EQ(r.stats.face_merges, 1u);
}

// Two wall faces `apart` metres apart (bands of occupied cells), unknown between, free outside.
LabelGrid twoFaces(double x0, double x1, double apart, double w = 8.0, double h = 5.0) {
  LabelGrid g = gridWith(
      {seg(x0, 2.0, x1, 2.0, Material::Wall, 0.05), seg(x0, 2.0 + apart, x1, 2.0 + apart, Material::Wall, 0.05)}, w, h);
  for (int x = 0; x < g.width; ++x)
    for (int y = 0; y < g.height; ++y) {
      const Vec2 c = g.center(x, y);
      if (c.x() > x0 && c.x() < x1 && c.y() > 2.05 && c.y() < 1.95 + apart)
        g.codes[static_cast<std::size_t>(y) * g.width + x] = kCodeUnknown;
    }
  return g;
}

TEST(Vectorize, AThickWallSeenFromBothSidesIsOneCentreLine) {
  // 0.6 m of masonry, 6 m long, rooms on both sides: one wall on its centre line with its thickness.
  const LabelGrid g = twoFaces(1.0, 7.0, 0.6);
  const VectorizeResult r = vectorize(g);
  const auto walls = ofMaterial(r.map, Material::Wall);
  ASSERT_EQ(walls.size(), 1u);
  EXPECT_NEAR(0.5 * (walls[0].a.y() + walls[0].b.y()), 2.3, 0.03);
  EXPECT_NEAR(walls[0].thickness, 0.65, 0.06);
  // Faces farther apart than a wall is thick stay two.
  VectorizeOptions o;
  o.max_two_sided_thickness = o.max_wall_thickness;
  EXPECT_EQ(ofMaterial(vectorize(g, o).map, Material::Wall).size(), 2u);
}

TEST(Vectorize, AThickWallSeenInPiecesIsOneCentreLine) {
  // 0.6 m of masonry, 10 m long, rooms on both sides; its lower face was seen only in two pieces
  // (3 and 4.5 m, the 2.5 m between them never seen, as a laser SLAM leaves a face it glimpsed).
  // Each piece is shorter than half the upper face, so neither merges with it, and too far from
  // the other for the plain fit to join them. The line the structure step joins across the unseen
  // gap does merge: one wall on the centre line, with its thickness, as long as the wall.
  LabelGrid g = twoFaces(1.0, 11.0, 0.6, 12.0, 6.0);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const Vec2 c = g.center(x, y);
      if (c.x() > 4.0 && c.x() < 6.5 && c.y() > 1.5 && c.y() < 2.1)
        g.codes[static_cast<std::size_t>(y) * g.width + x] = kCodeUnknown;
    }
  const VectorizeResult r = vectorize(g);
  const auto walls = ofMaterial(r.map, Material::Wall);
  ASSERT_EQ(walls.size(), 1u);
  EXPECT_NEAR(0.5 * (walls[0].a.y() + walls[0].b.y()), 2.3, 0.03);
  EXPECT_NEAR(walls[0].thickness, 0.65, 0.06);
  EXPECT_NEAR(walls[0].length(), 10.0, 0.3);
}

TEST(Vectorize, ADeskAgainstAWallIsNotAThickWall) {
  // 1.5 m long, 0.6 m from its front to the wall's other face, free outside both: as long as
  // furniture, so two faces (the plain fit keeps such short pieces as walls).
  VectorizeOptions o;
  o.structure.enabled = false;
  const VectorizeResult r = vectorize(twoFaces(2.0, 3.5, 0.6), o);
  const auto walls = ofMaterial(r.map, Material::Wall);
  ASSERT_EQ(walls.size(), 2u);
  for (const MapSegment& w : walls) EXPECT_LT(w.thickness, 0.2);
  EXPECT_EQ(r.stats.face_merges, 0u);
}

TEST(Vectorize, LongThickWallIsNotSplit) {
  const LabelGrid g = gridWith({seg(0.3, 2.0, 9.7, 2.0, Material::Wall, 0.3)}, 10.0, 4.0);
  const VectorizeResult r = vectorize(g);
  ASSERT_EQ(r.map.segments.size(), 1u);
  EXPECT_NEAR(r.map.segments[0].length(), 9.55, 0.15);  // 9.4 m plus round caps of the raster
  EXPECT_EQ(r.stats.bic_splits, 0u);
}

TEST(Vectorize, BentPaneIsSplitByTheCriterion) {
  // Two glass panes meeting at 10 degrees, labelled alike (as a coarse classifier would): one
  // region, but two lines explain the cells far better than one.
  const double a = deg2rad(10.0);
  LabelGrid g = gridWith({seg(0.5, 2.0, 3.0, 2.0, Material::Glass, 0.01),
                          seg(3.0, 2.0, 3.0 + 2.5 * std::cos(a), 2.0 + 2.5 * std::sin(a), Material::Glass, 0.01)});
  for (auto& c : g.codes)
    if (isGlassCode(c)) c = glassCodeOf(kPi / 2);
  const VectorizeResult r = vectorize(g);
  const auto glass = ofMaterial(r.map, Material::Glass);
  ASSERT_EQ(glass.size(), 2u);
  std::vector<double> errs = {std::min(directionErrorDeg(glass[0], 0.0), directionErrorDeg(glass[0], a)),
                              std::min(directionErrorDeg(glass[1], 0.0), directionErrorDeg(glass[1], a))};
  EXPECT_LT(errs[0], 1.0);
  EXPECT_LT(errs[1], 1.0);
}

TEST(Vectorize, CollinearPanesMergeAcrossSmallGapsOnly) {
  VectorizeOptions opt;
  ASSERT_DOUBLE_EQ(opt.glass.merge_gap, 0.30);
  {  // 0.1 m gap (a mullion): one segment
    const LabelGrid g =
        gridWith({seg(0.5, 2.0, 2.5, 2.0, Material::Glass, 0.01), seg(2.6, 2.0, 5.0, 2.0, Material::Glass, 0.01)});
    const auto glass = ofMaterial(vectorize(g, opt).map, Material::Glass);
    ASSERT_EQ(glass.size(), 1u);
    EXPECT_TRUE(sameEnds(glass[0], Vec2(0.5, 2.0), Vec2(5.0, 2.0), 0.08));
  }
  {  // 0.6 m gap, twice the merge gap: two segments
    const LabelGrid g =
        gridWith({seg(0.5, 2.0, 2.5, 2.0, Material::Glass, 0.01), seg(3.1, 2.0, 5.0, 2.0, Material::Glass, 0.01)});
    const auto glass = ofMaterial(vectorize(g, opt).map, Material::Glass);
    ASSERT_EQ(glass.size(), 2u);
    for (const MapSegment& s : glass)
      EXPECT_TRUE(sameEnds(s, Vec2(0.5, 2.0), Vec2(2.5, 2.0), 0.08) ||
                  sameEnds(s, Vec2(3.1, 2.0), Vec2(5.0, 2.0), 0.08));
  }
  {  // parallel panes 0.3 m apart never merge
    const LabelGrid g =
        gridWith({seg(0.5, 2.0, 5.0, 2.0, Material::Glass, 0.01), seg(0.5, 2.3, 5.0, 2.3, Material::Glass, 0.01)});
    EXPECT_EQ(ofMaterial(vectorize(g, opt).map, Material::Glass).size(), 2u);
  }
}

TEST(Vectorize, NoiseBlobsDoNotBecomeGlass) {
  LabelGrid g = gridWith({});
  addSalt(g, 0.03, 11, true);
  // Compact blobs of one label, up to 5 x 5 cells, as a noisy classifier leaves around clutter.
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> px(5, g.width - 10), py(5, g.height - 10), size(2, 5), bin(0, 35);
  for (int b = 0; b < 40; ++b) {
    const int x0 = px(rng), y0 = py(rng), s = size(rng);
    const auto code = static_cast<std::uint8_t>(kCodeFirstGlass + bin(rng));
    for (int y = y0; y < y0 + s; ++y)
      for (int x = x0; x < x0 + s; ++x) g.codes[static_cast<std::size_t>(y) * g.width + x] = code;
  }
  const VectorizeResult r = vectorize(g);
  for (const MapSegment& s : ofMaterial(r.map, Material::Glass))
    ADD_FAILURE() << "glass " << s.a.transpose() << " -> " << s.b.transpose() << " support " << s.support;
  EXPECT_GT(r.stats.glass_cells, 500u);
}

TEST(Vectorize, RoomOfWallsGivesFourClosedWalls) {
  const LabelGrid g = gridWith({seg(1, 1, 5, 1, Material::Wall, 0.15), seg(5, 1, 5, 4, Material::Wall, 0.15),
                                seg(5, 4, 1, 4, Material::Wall, 0.15), seg(1, 4, 1, 1, Material::Wall, 0.15)});
  const VectorizeResult r = vectorize(g);
  ASSERT_EQ(r.map.segments.size(), 4u);
  const std::vector<Vec2> corners = {{1, 1}, {5, 1}, {5, 4}, {1, 4}};
  for (const MapSegment& s : r.map.segments)
    for (const Vec2& e : {s.a, s.b}) {
      double best = 1e9;
      for (const Vec2& c : corners) best = std::min(best, (e - c).norm());
      EXPECT_LT(best, 0.06) << "end " << e.transpose();
    }
}

TEST(Vectorize, EvidenceAndSupportAttributes) {
  LabelGrid g = gridWith({seg(1.0, 2.025, 4.0, 2.025, Material::Glass, 0.01)});  // along cell centres
  g.evidence.assign(g.cells(), 0.25f);
  const auto glass = ofMaterial(vectorize(g).map, Material::Glass);
  ASSERT_EQ(glass.size(), 1u);
  EXPECT_NEAR(glass[0].evidence, 0.25, 1e-6);
  EXPECT_NEAR(glass[0].support, 60u, 1u);  // 3 m of 5 cm cells, one row (+ the end cell the raster touches)
}

// The glass segment of `map` nearest to p (its nearer end), and that end.
Vec2 glassEndNear(const VectorMap& map, const Vec2& p) {
  Vec2 best = Vec2::Constant(1e9);
  for (const MapSegment& s : ofMaterial(map, Material::Glass))
    for (const Vec2& e : {s.a, s.b})
      if ((e - p).norm() < (best - p).norm()) best = e;
  return best;
}

TEST(Vectorize, PaneEndsInTheWallItPointsAt) {
  // A pane whose last 0.5 m before a wall were labelled empty (its cells there seen only at wide
  // angles, or lost to the MRF): its end moves onto the wall. A 0.8 m gap is a passage and stays.
  VectorizeOptions opt;
  ASSERT_DOUBLE_EQ(opt.glass_corner_snap, 0.6);
  const MapSegment wall = seg(4.5, 0.5, 4.5, 4.5, Material::Wall, 0.15);
  {
    const VectorizeResult r = vectorize(gridWith({wall, seg(1.0, 2.0, 4.0, 2.0, Material::Glass, 0.01)}), opt);
    const Vec2 end = glassEndNear(r.map, Vec2(4.5, 2.0));
    EXPECT_LT((end - Vec2(4.5, 2.0)).norm(), 0.08) << end.transpose();
  }
  {
    const VectorizeResult r = vectorize(gridWith({wall, seg(1.0, 2.0, 3.7, 2.0, Material::Glass, 0.01)}), opt);
    const Vec2 end = glassEndNear(r.map, Vec2(4.5, 2.0));
    EXPECT_LT((end - Vec2(3.7, 2.0)).norm(), 0.08) << end.transpose();
  }
}

TEST(Vectorize, PaneDoesNotGrowOverTheWallItRunsOnAs) {
  // A pane whose line runs on as a wall, a cross wall 0.5 m along: the pane ends where the wall
  // begins, not at the cross wall.
  const VectorizeResult r = vectorize(
      gridWith({seg(1.0, 2.0, 3.5, 2.0, Material::Glass, 0.01), seg(3.5, 2.0, 5.5, 2.0, Material::Wall, 0.15),
                seg(4.0, 2.0, 4.0, 4.5, Material::Wall, 0.15), seg(5.5, 0.5, 5.5, 4.5, Material::Wall, 0.15)}));
  const Vec2 end = glassEndNear(r.map, Vec2(3.5, 2.0));
  EXPECT_LT((end - Vec2(3.5, 2.0)).norm(), 0.08) << end.transpose();
}

TEST(Vectorize, AWallStubAPanePointsAtIsStructure) {
  // A steep pane stops 0.45 m short of a 1 m wall stub that hangs off a long wall: the stub is
  // the pane's frame (a wall, not furniture hanging by one end), and the pane ends on it.
  const VectorizeResult r =
      vectorize(gridWith({seg(5.0, 0.5, 5.0, 4.5, Material::Wall, 0.15), seg(4.05, 4.0, 5.0, 4.0, Material::Wall, 0.15),
                          seg(4.4, 1.0, 4.1, 3.55, Material::Glass, 0.01)}));
  const auto walls = ofMaterial(r.map, Material::Wall);
  const bool stub = std::any_of(walls.begin(), walls.end(), [](const MapSegment& w) {
    return directionErrorDeg(w, 0.0) < 2.0 && std::abs(w.a.y() - 4.0) < 0.08 && std::min(w.a.x(), w.b.x()) < 4.2;
  });
  EXPECT_TRUE(stub) << "the stub went to clutter";
  // Where the pane's line crosses the stub's: y = 4, x = 4.1 - 0.45 * 0.3 / 2.55.
  const Vec2 end = glassEndNear(r.map, Vec2(4.05, 4.0));
  EXPECT_LT((end - Vec2(4.1 - 0.45 * 0.3 / 2.55, 4.0)).norm(), 0.08) << end.transpose();
}

}  // namespace
}  // namespace glassmap::vector

namespace glassmap::vector {
namespace {

TEST(Vectorize, WallGapsBridgeWhenUnseenButDoorsStayOpen) {
  // Two collinear walls 1.2 m apart: past merge_gap (0.5 m), within max_bridge (2 m).
  const std::vector<MapSegment> walls = {seg(0.5, 2.0, 2.5, 2.0, Material::Wall, 0.1),
                                         seg(3.7, 2.0, 5.5, 2.0, Material::Wall, 0.1)};
  LabelGrid door = gridWith(walls);  // the gap was seen free: a door
  EXPECT_EQ(ofMaterial(vectorize(door).map, Material::Wall).size(), 2u);
  LabelGrid unseen = gridWith(walls);  // the gap was never observed: one wall hit in patches
  for (int y = 0; y < unseen.height; ++y)
    for (int x = 0; x < unseen.width; ++x) {
      const Vec2 c = unseen.center(x, y);
      if (c.x() > 2.6 && c.x() < 3.6 && std::abs(c.y() - 2.0) < 0.3)
        unseen.codes[static_cast<std::size_t>(y) * unseen.width + x] = kCodeUnknown;
    }
  const auto merged = ofMaterial(vectorize(unseen).map, Material::Wall);
  ASSERT_EQ(merged.size(), 1u);
  EXPECT_TRUE(sameEnds(merged[0], Vec2(0.5, 2.0), Vec2(5.5, 2.0), 0.1));
}

}  // namespace
}  // namespace glassmap::vector
