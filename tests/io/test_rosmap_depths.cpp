// Map images of other bit depths, read as map_server's image loader expands them: a 1-bit PNG
// (white = 1 in the file) is free, not occupied; 16-bit grey by 65535; a paletted PNG through its
// colours, not its indices.
#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "glassmap/io/ros_map.hpp"
#include "io_test_util.hpp"

namespace glassmap {
namespace {

using test::TempDir;

const char* kYaml = "image: m.png\nresolution: 0.5\norigin: [0, 0, 0]\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";

// Writes a 2 x 2 PNG from a MEM dataset of `type` (values row by row, top row first).
template <typename T>
void writePng(const TempDir& dir, GDALDataType type, const std::vector<T>& px, const char* nbits = nullptr,
              const GDALColorTable* palette = nullptr) {
  GDALAllRegister();
  GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
  GDALDriver* drv = GetGDALDriverManager()->GetDriverByName("PNG");
  ASSERT_TRUE(mem && drv);
  GDALDatasetUniquePtr src(mem->Create("", 2, 2, 1, type, nullptr));
  ASSERT_EQ(src->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, 2, 2, const_cast<T*>(px.data()), 2, 2, type, 0, 0, nullptr),
            CE_None);
  if (palette) src->GetRasterBand(1)->SetColorTable(const_cast<GDALColorTable*>(palette));
  CPLStringList options;
  if (nbits) options.SetNameValue("NBITS", nbits);
  GDALDatasetUniquePtr out(
      drv->CreateCopy((dir / "m.png").string().c_str(), src.get(), FALSE, options.List(), nullptr, nullptr));
  ASSERT_TRUE(out);
}

TEST(RosMapDepths, OneBitWhiteIsFree) {
  TempDir dir;
  writePng<std::uint8_t>(dir, GDT_Byte, {0, 1, 1, 0}, "1");
  dir.write("m.yaml", kYaml);
  const OccupancyGridMap m = readRosMap(dir / "m.yaml");
  EXPECT_EQ(m.at(0, 1), 100);  // top left black
  EXPECT_EQ(m.at(1, 1), 0);    // top right white
  EXPECT_EQ(m.at(0, 0), 0);
  EXPECT_EQ(m.at(1, 0), 100);
}

TEST(RosMapDepths, SixteenBitGreyScalesBy65535) {
  TempDir dir;
  writePng<std::uint16_t>(dir, GDT_UInt16, {0, 65535, 52685, 65000});
  dir.write("m.yaml", kYaml);
  const OccupancyGridMap m = readRosMap(dir / "m.yaml");
  EXPECT_EQ(m.at(0, 1), 100);
  EXPECT_EQ(m.at(1, 1), 0);
  EXPECT_EQ(m.at(0, 0), -1);  // 0.804 of white: between the thresholds
  EXPECT_EQ(m.at(1, 0), 0);
}

TEST(RosMapDepths, PalettedPngReadsItsColours) {
  TempDir dir;
  GDALColorTable palette;
  const GDALColorEntry white{255, 255, 255, 255}, black{0, 0, 0, 255}, grey{205, 205, 205, 255};
  palette.SetColorEntry(0, &white);  // index 0 white: read as an index it would be black
  palette.SetColorEntry(1, &black);
  palette.SetColorEntry(2, &grey);
  writePng<std::uint8_t>(dir, GDT_Byte, {1, 0, 2, 0}, nullptr, &palette);
  dir.write("m.yaml", kYaml);
  const OccupancyGridMap m = readRosMap(dir / "m.yaml");
  EXPECT_EQ(m.at(0, 1), 100);
  EXPECT_EQ(m.at(1, 1), 0);
  EXPECT_EQ(m.at(0, 0), -1);
  EXPECT_EQ(m.at(1, 0), 0);
}

}  // namespace
}  // namespace glassmap
