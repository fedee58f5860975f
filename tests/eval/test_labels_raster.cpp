// GeoTIFF label rasters (io/labels_raster): round trip, orientation, errors.
#include <gtest/gtest.h>

#include <filesystem>

#include "glassmap/core/error.hpp"
#include "glassmap/io/labels_raster.hpp"

namespace glassmap {
namespace {

TEST(LabelRaster, RoundTripKeepsCodesGeometryAndBottomRow) {
  const auto dir = std::filesystem::path(GLASSMAP_BINARY_DIR) / "test_eval_out";
  std::filesystem::create_directories(dir);
  LabelRaster r;
  r.width = 5;
  r.height = 3;
  r.resolution = 0.05;
  r.origin = Vec2(-1.25, 2.5);
  r.codes = {1, 1, 2, 10, 45,                   // bottom row
             0, 0, 0, 0,  0,  2, 2, 2, 2, 17};  // top row
  writeLabelRaster(dir / "labels.tif", r);
  const LabelRaster back = readLabelRaster(dir / "labels.tif");
  EXPECT_EQ(back.width, 5);
  EXPECT_EQ(back.height, 3);
  EXPECT_DOUBLE_EQ(back.resolution, 0.05);
  EXPECT_NEAR(back.origin.x(), -1.25, 1e-12);
  EXPECT_NEAR(back.origin.y(), 2.5, 1e-12);
  EXPECT_EQ(back.codes, r.codes);
  // No temporary left behind.
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    files += entry.path().filename().string()[0] == '.';
  EXPECT_EQ(files, 0);
}

TEST(LabelRaster, Errors) {
  const auto dir = std::filesystem::path(GLASSMAP_BINARY_DIR) / "test_eval_out";
  std::filesystem::create_directories(dir);
  LabelRaster r;
  r.width = 2;
  r.height = 2;
  r.codes = {1, 2, 3};
  EXPECT_THROW(writeLabelRaster(dir / "bad.tif", r), Error);
  EXPECT_FALSE(std::filesystem::exists(dir / "bad.tif"));
  EXPECT_THROW(readLabelRaster(dir / "missing.tif"), Error);
}

}  // namespace
}  // namespace glassmap
