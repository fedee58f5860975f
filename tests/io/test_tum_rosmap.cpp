#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "glassmap/core/error.hpp"
#include "glassmap/io/ros_map.hpp"
#include "glassmap/io/tum.hpp"
#include "io_test_util.hpp"

namespace glassmap {
namespace {

using test::TempDir;

TEST(Tum, RoundTrip) {
  TempDir dir;
  std::vector<StampedPose> poses;
  for (int i = 0; i < 20; ++i) {
    StampedPose p;
    p.timestamp = 1071078718.462310 + 0.1 * i;
    p.pose = Pose2(0.1 * i - 3.0, 1.0 / (i + 1), -kPi + 0.33 * i);
    poses.push_back(p);
  }
  writeTum(dir / "traj.txt", poses);
  const auto back = readTum(dir / "traj.txt");
  ASSERT_EQ(back.size(), poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    EXPECT_EQ(back[i].timestamp, poses[i].timestamp);
    EXPECT_TRUE(approxEqual(back[i].pose, poses[i].pose, 0.0, 1e-12)) << i;
  }
}

TEST(Tum, ReadsForeignLinesAndRejectsBadOnes) {
  TempDir dir;
  // Yaw of 90 degrees as an unnormalised quaternion, comments and blank lines.
  const auto ok = dir.write("a.tum", "# header\n\n1.5 1 2 0.3 0 0 2 2\n");
  const auto poses = readTum(ok);
  ASSERT_EQ(poses.size(), 1u);
  EXPECT_NEAR(poses[0].pose.theta, kPi / 2, 1e-12);
  EXPECT_DOUBLE_EQ(poses[0].pose.x(), 1.0);
  const auto few = dir.write("b.tum", "1 2 3\n");
  try {
    readTum(few);
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_EQ(e.line(), 1u);
    EXPECT_NE(std::string(e.what()).find("8 values"), std::string::npos);
  }
  const auto letters = dir.write("c.tum", "# x\n1 2 3 4 0 0 0 1\n1 2 y 4 0 0 0 1\n");
  try {
    readTum(letters);
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_EQ(e.line(), 3u);
    EXPECT_EQ(e.field(), "y");
  }
  EXPECT_THROW(readTum(dir.write("d.tum", "1 2 3 4 0 0 0 0\n")), Error);
  EXPECT_THROW(readTum(dir / "missing.tum"), Error);
}

OccupancyGridMap sampleGrid() {
  OccupancyGridMap m;
  m.width = 7;
  m.height = 4;
  m.resolution = 0.05;
  m.origin = Pose2(-1.25, 3.5, 0.0);
  m.data.resize(28);
  for (int i = 0; i < 28; ++i)
    m.data[static_cast<std::size_t>(i)] = static_cast<std::int8_t>(i % 3 == 0 ? -1 : i % 3 == 1 ? 0 : 100);
  m.data[0] = 100;  // bottom-left cell occupied: tells the row flip
  return m;
}

TEST(RosMap, RoundTripWithRowFlip) {
  TempDir dir;
  const OccupancyGridMap map = sampleGrid();
  writeRosMap(dir / "map", map);  // stem: map.yaml + map.pgm
  ASSERT_TRUE(std::filesystem::exists(dir / "map.yaml"));
  ASSERT_TRUE(std::filesystem::exists(dir / "map.pgm"));
  const OccupancyGridMap back = readRosMap(dir / "map.yaml");
  EXPECT_EQ(back.width, map.width);
  EXPECT_EQ(back.height, map.height);
  EXPECT_DOUBLE_EQ(back.resolution, map.resolution);
  EXPECT_TRUE(approxEqual(back.origin, map.origin, 0.0, 0.0));
  EXPECT_EQ(back.data, map.data);
  // The PGM's last row (bottom of the picture) starts with the occupied bottom-left cell: 0 = black.
  std::ifstream in(dir / "map.pgm", std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GE(bytes.size(), 28u);
  const std::string pixels = bytes.substr(bytes.size() - 28);
  EXPECT_EQ(static_cast<unsigned char>(pixels[21]), 0);    // row 0, col 0 -> last image row
  EXPECT_EQ(static_cast<unsigned char>(pixels[22]), 254);  // data[1] = 0 -> free
  EXPECT_EQ(static_cast<unsigned char>(pixels[23]), 0);    // data[2] = 100 -> occupied
  EXPECT_EQ(static_cast<unsigned char>(pixels[24]), 205);  // data[3] = -1 -> unknown
}

TEST(RosMap, ReadsMapServerVariants) {
  TempDir dir;
  // ASCII PGM, negate, scale mode, image path relative to the yaml, top image row = top grid row.
  std::filesystem::create_directories(dir / "img");
  dir.write("img/m.pgm", "P2\n# c\n3 2\n255\n0 128 255\n255 255 0\n");
  dir.write("scale.yaml",
            "image: img/m.pgm\nresolution: 0.1\norigin: [1.0, 2.0, 0.0]\nnegate: 0\n"
            "occupied_thresh: 0.65\nfree_thresh: 0.196\nmode: scale\n");
  const OccupancyGridMap m = readRosMap(dir / "scale.yaml");
  ASSERT_EQ(m.width, 3);
  ASSERT_EQ(m.height, 2);
  // Bottom grid row = last image row "255 255 0".
  EXPECT_EQ(m.at(0, 0), 0);
  EXPECT_EQ(m.at(2, 0), 100);
  EXPECT_EQ(m.at(0, 1), 100);
  EXPECT_EQ(m.at(2, 1), 0);
  const int mid = m.at(1, 1);  // occ = 127/255 = 0.498 -> scaled between free and occupied
  EXPECT_GT(mid, 50);
  EXPECT_LT(mid, 80);
  dir.write("neg.yaml",
            "image: img/m.pgm\nresolution: 0.1\norigin: [0, 0, 0]\nnegate: 1\n"
            "occupied_thresh: 0.65\nfree_thresh: 0.196\n");
  const OccupancyGridMap n = readRosMap(dir / "neg.yaml");
  EXPECT_EQ(n.at(0, 0), 100);  // white is occupied when negated
  EXPECT_EQ(n.at(1, 1), -1);   // trinary: in between is unknown ...
  // ... its shade kept beside it (index row * width + col), with the thresholds it was read with.
  ASSERT_EQ(n.occupancy.size(), n.data.size());
  EXPECT_NEAR(n.occupancy[4], 128.0 / 255.0, 1e-6);  // negate: occupancy = v / 255
  EXPECT_NEAR(n.occupancy[0], 1.0, 1e-6);
  EXPECT_DOUBLE_EQ(n.occupied_thresh, 0.65);
  EXPECT_DOUBLE_EQ(n.free_thresh, 0.196);
  dir.write("raw.yaml", "image: img/m.pgm\nresolution: 0.1\norigin: [0, 0, 0]\nmode: raw\n");
  EXPECT_EQ(readRosMap(dir / "raw.yaml").at(1, 1), static_cast<std::int8_t>(128));
  EXPECT_TRUE(readRosMap(dir / "raw.yaml").occupancy.empty());  // raw values carry no shade
}

TEST(RosMap, ErrorsNameTheYaml) {
  TempDir dir;
  const auto y = dir.write("m.yaml", "image: nothere.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n");
  try {
    readRosMap(y);
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_EQ(e.file(), y.string());
    EXPECT_EQ(e.field(), "image");
    EXPECT_NE(std::string(e.what()).find("nothere.pgm"), std::string::npos);
  }
  const auto no_res = dir.write("r.yaml", "image: a.pgm\norigin: [0, 0, 0]\n");
  try {
    readRosMap(no_res);
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "resolution");
  }
  dir.write("short.pgm", "P5\n10 10\n255\nabc");
  const auto s = dir.write("s.yaml", "image: short.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n");
  EXPECT_THROW(readRosMap(s), Error);
  const auto bad_mode = dir.write("b.yaml", "image: short.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nmode: fancy\n");
  EXPECT_THROW(readRosMap(bad_mode), Error);
  EXPECT_THROW(readRosMap(dir.write("bad.yaml", "image: [unclosed\n")), Error);
  OccupancyGridMap wrong;
  wrong.width = 3;
  wrong.height = 3;
  wrong.data.resize(4);
  EXPECT_THROW(writeRosMap(dir / "w.yaml", wrong), Error);
  EXPECT_FALSE(std::filesystem::exists(dir / "w.pgm"));
}

}  // namespace
}  // namespace glassmap

#include <gdal_priv.h>

namespace glassmap {
namespace {

TEST(RosMap, ReadsPngThroughGdal) {
  GDALAllRegister();
  test::TempDir dir;
  const auto png = dir / "m.png";
  {
    GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
    GDALDriver* drv = GetGDALDriverManager()->GetDriverByName("PNG");
    ASSERT_TRUE(mem && drv);
    GDALDatasetUniquePtr src(mem->Create("", 2, 2, 1, GDT_Byte, nullptr));
    unsigned char px[4] = {0, 254, 205, 254};  // top row: occupied, free; bottom row: unknown, free
    ASSERT_EQ(src->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, 2, 2, px, 2, 2, GDT_Byte, 0, 0, nullptr), CE_None);
    GDALDatasetUniquePtr out(drv->CreateCopy(png.string().c_str(), src.get(), FALSE, nullptr, nullptr, nullptr));
    ASSERT_TRUE(out);
  }
  dir.write("m.yaml", "image: m.png\nresolution: 0.5\norigin: [0, 0, 0]\noccupied_thresh: 0.65\nfree_thresh: 0.196\n");
  const OccupancyGridMap m = readRosMap(dir / "m.yaml");
  ASSERT_EQ(m.width, 2);
  EXPECT_EQ(m.at(0, 1), 100);
  EXPECT_EQ(m.at(1, 1), 0);
  EXPECT_EQ(m.at(0, 0), -1);
  EXPECT_EQ(m.at(1, 0), 0);
}

}  // namespace
}  // namespace glassmap
