// Occupancy maps from other programs: only the faces of free space are walls; a ROS map's origin
// (with yaw) places the floorplan; an occupancy image is told apart from a label raster.
#include <gtest/gtest.h>

#include <cmath>

#include "glassmap/core/angles.hpp"
#include "glassmap/vector/from_occupancy.hpp"
#include "glassmap/vector/vectorize.hpp"

namespace glassmap::vector {
namespace {

// A 6 x 4 m room and a 1 x 1 m pillar inside it, drawn the map-editor way: everything that is
// not free space is occupied (the building's outside is solid black), 0.05 m cells.
OccupancyGridMap solidRoom(double yaw = 0.0) {
  OccupancyGridMap m;
  m.resolution = 0.05;
  m.width = 200;
  m.height = 160;
  m.origin = Pose2(10.0, -3.0, yaw);
  m.data.assign(static_cast<std::size_t>(m.width) * m.height, 100);
  for (int y = 0; y < m.height; ++y)
    for (int x = 0; x < m.width; ++x) {
      const double cx = (x + 0.5) * m.resolution, cy = (y + 0.5) * m.resolution;
      const bool room = cx > 2.0 && cx < 8.0 && cy > 2.0 && cy < 6.0;
      const bool pillar = cx > 4.0 && cx < 5.0 && cy > 3.5 && cy < 4.5;
      if (room && !pillar) m.data[static_cast<std::size_t>(y) * m.width + x] = 0;
    }
  return m;
}

double wallLength(const VectorMap& map) {
  double sum = 0;
  for (const MapSegment& s : map.segments)
    if (s.material == Material::Wall) sum += s.length();
  return sum;
}

TEST(FromOccupancy, SolidAreasGiveTheirFacesOnly) {
  OccupancyStats stats;
  const LabelGrid faces = fromOccupancy(solidRoom(), {}, &stats);
  EXPECT_GT(stats.solid_inside, 20000u);
  const VectorizeResult r = vectorize(faces);
  // Room perimeter 20 m, nothing hatched inside the solid black; the free-standing pillar (free
  // space again 1 m behind each face) is clutter, its 4 m of faces in the clutter layer.
  EXPECT_NEAR(wallLength(r.map), 20.0, 1.0);
  EXPECT_LE(r.map.count(Material::Wall), 4u);
  EXPECT_EQ(r.map.count(Material::Glass), 0u);
  EXPECT_NEAR(wallLength(r.extras.clutter), 3.6, 0.6);  // faces clipped to their cells at the corners
  // Keeping every occupied cell hatches the solid area with many parallel lines.
  OccupancyOptions keep;
  keep.face_cells = -1;
  VectorizeOptions plain;
  plain.structure.enabled = false;
  const VectorizeResult hatched = vectorize(fromOccupancy(solidRoom(), keep), plain);
  EXPECT_GT(wallLength(hatched.map), 3.0 * (wallLength(r.map) + wallLength(r.extras.clutter)));
}

// The same room as an image editor's anti-aliasing or a resampled map leaves it: a grey rim,
// unknown between the thresholds, one or two cells wide between the room and the black around it
// (and around the pillar). Free space reaches through the rim, so the walls are still the room's
// faces; without that every wall cell was parted from free space and dropped as a solid area's
// inside (no wall at all: tools/plan_bench.py maps blurred at 0.8 px gave wall F1 0).
TEST(FromOccupancy, AGreyRimDoesNotPartTheWallsFromTheRoom) {
  for (const int width : {1, 2}) {
    OccupancyGridMap m = solidRoom();
    const OccupancyGridMap sharp = m;
    for (int y = 1; y + 1 < m.height; ++y)
      for (int x = 1; x + 1 < m.width; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * m.width + x;
        if (sharp.data[i] != 100) continue;
        // Occupied cells within `width` cells of free space turn grey.
        bool near_free = false;
        for (int dy = -width; dy <= width && !near_free; ++dy)
          for (int dx = -width; dx <= width && !near_free; ++dx) {
            const int nx = x + dx, ny = y + dy;
            near_free = nx >= 0 && ny >= 0 && nx < m.width && ny < m.height &&
                        sharp.data[static_cast<std::size_t>(ny) * m.width + nx] == 0;
          }
        if (near_free) m.data[i] = 50;
      }
    OccupancyStats stats;
    const VectorizeResult r = vectorize(fromOccupancy(m, {}, &stats));
    EXPECT_NEAR(wallLength(r.map), 20.0, 1.5) << "rim " << width;
    EXPECT_LE(r.map.count(Material::Wall), 6u) << "rim " << width;
    OccupancyOptions no_rim;
    no_rim.rim_cells = 0;
    const VectorizeResult parted = vectorize(fromOccupancy(m, no_rim));
    EXPECT_LT(wallLength(parted.map), 1.0) << "rim " << width;
  }
}

// A 6 x 4 m room as a laser SLAM draws it: free inside, its walls a band one cell thin, unknown
// beyond, then blurred (a 1-2-1 kernel across rows and columns, as a resampling leaves it). The
// band turns grey: 115 at its middle, occupancy 0.55, under occupied_thresh 0.65, so the
// thresholds read it as unknown like the grey beyond it, and the room has no wall. It is darker than
// the cells either side of it, though, and nearer occupied than free: a ridge, read as occupied.
TEST(FromOccupancy, AThinWallABlurMadeGreyIsStillAWall) {
  LabelRaster img;
  img.width = 160;
  img.height = 120;
  img.resolution = 0.05;
  img.codes.assign(static_cast<std::size_t>(img.width) * img.height, 205);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const double cx = (x + 0.5) * img.resolution, cy = (y + 0.5) * img.resolution;
      const bool band = cx > 1.0 && cx < 7.1 && cy > 1.0 && cy < 5.1;
      const bool room = cx > 1.05 && cx < 7.05 && cy > 1.05 && cy < 5.05;
      std::uint8_t& v = img.codes[static_cast<std::size_t>(y) * img.width + x];
      if (band) v = room ? 254 : 0;
    }
  const auto blur = [&](int dx, int dy) {
    const std::vector<std::uint8_t> in = img.codes;
    for (int y = 1; y + 1 < img.height; ++y)
      for (int x = 1; x + 1 < img.width; ++x) {
        const auto at = [&](int xx, int yy) {
          return static_cast<double>(in[static_cast<std::size_t>(yy) * img.width + xx]);
        };
        img.codes[static_cast<std::size_t>(y) * img.width + x] = static_cast<std::uint8_t>(
            std::lround(0.25 * at(x - dx, y - dy) + 0.5 * at(x, y) + 0.25 * at(x + dx, y + dy)));
      }
  };
  blur(1, 0);
  blur(0, 1);
  OccupancyStats stats;
  const VectorizeResult r = vectorize(fromOccupancyRaster(img, 0.65, 0.196, {}, &stats));
  EXPECT_GT(stats.ridges, 300u);
  EXPECT_NEAR(wallLength(r.map), 20.0, 1.5);
  EXPECT_LE(r.map.count(Material::Wall), 6u);
  OccupancyOptions thresholds_only;
  thresholds_only.ridges = false;
  EXPECT_LT(wallLength(vectorize(fromOccupancyRaster(img, 0.65, 0.196, thresholds_only)).map), 1.0);
}

TEST(FromOccupancy, TheOriginAndItsYawPlaceTheFloorplan) {
  const double yaw = deg2rad(30.0);
  const OccupancyGridMap m = solidRoom(yaw);
  const VectorMap placed = placeOnPose(vectorize(fromOccupancy(m)).map, m.origin);
  // The room's corner (2, 2) in the grid lies at origin + R(yaw) (2, 2) in the map frame.
  const Vec2 corner = m.origin * Vec2(2.0, 2.0);
  double nearest = 1e9;
  for (const MapSegment& s : placed.segments)
    nearest = std::min({nearest, (s.a - corner).norm(), (s.b - corner).norm()});
  EXPECT_LT(nearest, 0.1);
}

TEST(FromOccupancy, OccupancyImagesAreToldFromLabelRasters) {
  LabelRaster labels;
  labels.width = 3;
  labels.height = 1;
  labels.codes = {kCodeEmpty, kCodeOccupied, static_cast<std::uint8_t>(kCodeFirstGlass + 4)};
  EXPECT_TRUE(looksLikeLabelCodes(labels));
  LabelRaster image = labels;
  image.codes = {254, 0, 205};
  EXPECT_FALSE(looksLikeLabelCodes(image));
  const LabelGrid g = fromOccupancyRaster(image, 0.65, 0.196, OccupancyOptions{-1});
  EXPECT_EQ(g.codes[0], kCodeEmpty);
  EXPECT_EQ(g.codes[1], kCodeOccupied);
  EXPECT_EQ(g.codes[2], kCodeUnknown);
}

}  // namespace
}  // namespace glassmap::vector
