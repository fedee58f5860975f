#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "glassmap/core/error.hpp"
#include "glassmap/core/labels.hpp"
#include "glassmap/io/render_labels.hpp"
#include "io_test_util.hpp"

namespace glassmap {
namespace {

// RGB of pixel (col, row) of a PNG, row 0 at the top, read back through GDAL.
std::array<int, 3> pixel(const std::filesystem::path& png, int col, int row) {
  GDALAllRegister();
  GDALDataset* ds = static_cast<GDALDataset*>(GDALOpen(png.string().c_str(), GA_ReadOnly));
  if (ds == nullptr) throw Error("cannot open", png.string());
  std::array<int, 3> rgb{};
  for (int b = 0; b < 3; ++b) {
    std::uint8_t v = 0;
    if (ds->GetRasterBand(b + 1)->RasterIO(GF_Read, col, row, 1, 1, &v, 1, 1, GDT_Byte, 0, 0) != CE_None) {
      GDALClose(ds);
      throw Error("cannot read", png.string());
    }
    rgb[static_cast<std::size_t>(b)] = v;
  }
  GDALClose(ds);
  return rgb;
}

TEST(RenderLabels, ColoursEachLabelWithRowZeroAtTheBottom) {
  test::TempDir dir;
  // Cells (x, y): (0,0) unknown, (1,0) empty, (0,1) occupied, (1,1) glass in bin 9.
  const std::vector<std::uint8_t> labels = {kUnknown, kEmpty, kOccupied, static_cast<std::uint8_t>(glassLabel(9))};
  const auto png = dir.path() / "tiny.png";
  LabelRenderOptions one_px;
  one_px.scale = 1;
  writeLabelsPng(png, 2, 2, labels, kDefaultBins, one_px);
  EXPECT_EQ(pixel(png, 0, 1), (std::array<int, 3>{205, 205, 205}));  // bottom-left: unknown
  EXPECT_EQ(pixel(png, 1, 1), (std::array<int, 3>{255, 255, 255}));  // bottom-right: empty
  EXPECT_EQ(pixel(png, 0, 0), (std::array<int, 3>{0, 0, 0}));        // top-left: occupied
  const Rgb g = labelColour(glassLabel(9), kDefaultBins);
  EXPECT_EQ(pixel(png, 1, 0), (std::array<int, 3>{g.r, g.g, g.b}));  // top-right: glass
  // Glass hue follows the pane angle: bins 0 and 18 (0 and 90 deg) differ, 0 and 36 cannot occur.
  const Rgb a = labelColour(glassLabel(0), kDefaultBins), b = labelColour(glassLabel(18), kDefaultBins);
  EXPECT_FALSE(a.r == b.r && a.g == b.g && a.b == b.b);
}

TEST(RenderLabels, RefusesASizeMismatchAndLeavesNoFile) {
  test::TempDir dir;
  const std::vector<std::uint8_t> labels(4, kEmpty);
  EXPECT_THROW(writeLabelsPng(dir.path() / "bad.png", 3, 2, labels, kDefaultBins), Error);
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "bad.png"));
}

}  // namespace
}  // namespace glassmap
