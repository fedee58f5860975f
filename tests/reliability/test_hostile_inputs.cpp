// Reliability (issue 9), readers: hostile inputs give a clear Error or a counted skip, never a
// crash, hang, absurd allocation or silent garbage.
#include <gdal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "glassmap/core/angles.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/geometry/ray_caster.hpp"
#include "glassmap/io/carmen.hpp"
#include "glassmap/io/floorplan.hpp"
#include "glassmap/io/labels_raster.hpp"
#include "glassmap/io/ros_map.hpp"
#include "glassmap/io/tum.hpp"
#include "reliability/reliability_util.hpp"

#if defined(__SANITIZE_ADDRESS__)
// AddressSanitizer keeps freed blocks in a quarantine (256 MiB by default), which would show up as
// RSS growth in the streaming test; a small quarantine keeps that test about the reader's memory.
extern "C" const char* __asan_default_options() { return "quarantine_size_mb=8"; }
#endif

namespace glassmap {
namespace {

using namespace reliability;

// ---------------------------------------------------------------------------------------------
// CARMEN logs

TEST(HostileLog, NonFiniteNegativeAndAbsurdRangesBecomeCountedNoReturns) {
  TempDir dir;
  const auto log = dir.write("a.clf", flaser({"1.5", "nan", "inf", "-inf", "-2", "1e30", "1e300", "2.5"}, 1.0));
  const LaserLog l = readCarmenLog(log);
  ASSERT_EQ(l.scans.size(), 1u);
  const auto& r = l.scans[0].ranges;
  ASSERT_EQ(r.size(), 8u);
  EXPECT_FLOAT_EQ(r[0], 1.5f);
  EXPECT_FLOAT_EQ(r[7], 2.5f);
  for (int i = 1; i <= 6; ++i) {
    EXPECT_EQ(r[static_cast<std::size_t>(i)], kNoReturn) << "beam " << i;
    EXPECT_FALSE(l.scans[0].isReturn(static_cast<std::size_t>(i)));
  }
  EXPECT_EQ(l.stats.no_return_ranges, 6u);
}

TEST(HostileLog, NonFinitePoseOrTimestampIsAnErrorNamingTheField) {
  TempDir dir;
  const auto bad_pose = dir.write("p.clf", "FLASER 2 1 1 nan 2 0 1 2 0 5 host 5\n");
  expectErrorAt([&] { readCarmenLog(bad_pose); }, "x", 1);
  const auto bad_time = dir.write("t.clf", "ODOM 1 2 0 0 0 0 inf host 5\n");
  CarmenReadOptions no_scans;
  no_scans.require_scans = false;
  expectErrorAt([&] { readCarmenLog(bad_time, no_scans); }, "timestamp");
  const auto bad_range_cfg =
      dir.write("c.clf", "ROBOTLASER1 0 -1.57 3.14 0.0174 nan 0.01 0 2 1 1 1 2 0 1 2 0 0 0 0 0 0 7 host 7\n");
  expectErrorAt([&] { readCarmenLog(bad_range_cfg); }, "maximum_range");
}

TEST(HostileLog, BeamCountsThatDisagreeWithTheHeaderAreErrors) {
  TempDir dir;
  const std::vector<std::string> four(4, "1.0");
  for (long declared : {3L, 5L, 100L}) {
    SCOPED_TRACE(declared);
    const auto p = dir.write("n" + std::to_string(declared) + ".clf", "# c\n" + flaser(four, 1.0, declared));
    expectErrorAt([&] { readCarmenLog(p); }, "num_readings", 2);
  }
  // Absurd or negative counts are refused before anything is allocated.
  expectErrorWith([&] { readCarmenLog(dir.write("huge.clf", flaser(four, 1.0, 4'000'000'000L))); },
                  "implausible count");
  expectErrorWith([&] { readCarmenLog(dir.write("neg.clf", "FLASER -4 1 1 1 1 1 2 0 1 2 0 5 host 5\n")); },
                  "implausible count");
  // ROBOTLASER1 declaring 3 beams but carrying 2 (and no remission block).
  const auto rl =
      dir.write("rl.clf", "ROBOTLASER1 0 -1.57 3.14 0.0174 80 0.01 0 3 1 1 1 2 0 1 2 0 0 0 0 0 0 7 host 7\n");
  EXPECT_THROW(readCarmenLog(rl), Error);
}

TEST(HostileLog, ZeroLengthScansAreReadAsEmptyScans) {
  TempDir dir;
  const auto p = dir.write(
      "z.clf", flaser({}, 1.0) + flaser({"1", "2"}, 2.0) + "RAWLASER1 0 -1.57 3.14 0.0174 80 0.01 0 0 0 3 host 3\n");
  const LaserLog l = readCarmenLog(p);
  ASSERT_EQ(l.scans.size(), 3u);
  EXPECT_TRUE(l.scans[0].ranges.empty());
  EXPECT_EQ(l.scans[0].fieldOfView(), 0.0);
  EXPECT_TRUE(l.scans[2].ranges.empty());
  EXPECT_TRUE(std::isfinite(l.scans[0].angular_step));
}

TEST(HostileLog, TimestampsGoingBackwardsOrRepeatingAreCounted) {
  TempDir dir;
  const std::vector<std::string> r = {"1", "2"};
  const auto p = dir.write(
      "t.clf", flaser(r, 5.0) + flaser(r, 5.0) + flaser(r, 4.0) + flaser(r, 6.0) + flaser(r, 6.0) + flaser(r, 1.0));
  const LaserLog l = readCarmenLog(p);
  ASSERT_EQ(l.scans.size(), 6u);  // kept in file order: mapping uses the poses, not the clock
  EXPECT_EQ(l.stats.backward_timestamps, 2u);
  EXPECT_EQ(l.stats.repeated_timestamps, 2u);
  std::size_t streamed = 0;
  CarmenCallbacks cb;
  cb.on_scan = [&](LaserScan&&) { ++streamed; };
  const LogReadStats s = forEachCarmenRecord(p, cb);
  EXPECT_EQ(streamed, 6u);
  EXPECT_EQ(s.backward_timestamps, 2u);
  EXPECT_EQ(s.repeated_timestamps, 2u);
}

TEST(HostileLog, AFileWithoutLineBreaksIsRefusedInBoundedMemory) {
  TempDir dir;
  const fs::path p = dir / "one-line.clf";
  {
    std::ofstream out(p, std::ios::binary);
    const std::string block(1 << 20, 'x');
    for (int i = 0; i < 80; ++i) out << block;  // 80 MiB, no '\n'
  }
  expectErrorWith([&] { forEachCarmenRecord(p, {}); }, "line longer than 64 MiB");
}

/// Current resident set size of this process [KiB].
long rssKib() {
  long pages_total = 0, pages_resident = 0;
  std::FILE* f = std::fopen("/proc/self/statm", "r");
  if (!f) return 0;
  if (std::fscanf(f, "%ld %ld", &pages_total, &pages_resident) != 2) pages_resident = 0;
  std::fclose(f);
  return pages_resident * (::sysconf(_SC_PAGESIZE) / 1024);
}

// A log gigabytes long, streamed: a writer thread generates it into a FIFO (nothing touches the
// disk), forEachCarmenRecord reads it, and the resident set (sampled every 1000 scans) must not
// grow with the log. 1 GiB in a
// plain build, 128 MiB under the sanitizers (which parse ~10x slower); the size is reported.
TEST(HostileLog, AGigabyteLogStreamsInBoundedMemory) {
  TempDir dir;
  const fs::path fifo = dir / "big.clf";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const std::size_t target_bytes = kSanitized ? (std::size_t{128} << 20) : (std::size_t{1} << 30);
  // One block of 64 scans of 361 beams with ODOM lines, repeated with increasing time.
  std::string block;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> range(0.5, 30.0);
  for (int k = 0; k < 64; ++k) {
    char buf[64];
    block += "FLASER 361";
    for (int i = 0; i < 361; ++i) {
      std::snprintf(buf, sizeof buf, " %.2f", range(rng));
      block += buf;
    }
    block += " 1.5 2.5 0.1 1.5 2.5 0.1 100.0 host 100.0\nODOM 1.5 2.5 0.1 0 0 0 100.0 host 100.0\n";
  }
  const std::size_t blocks = target_bytes / block.size() + 1;
  std::thread writer([&] {
    const int fd = ::open(fifo.c_str(), O_WRONLY);
    if (fd < 0) return;
    for (std::size_t b = 0; b < blocks; ++b) {
      for (std::size_t off = 0; off < block.size();) {
        const ssize_t n = ::write(fd, block.data() + off, block.size() - off);
        if (n <= 0) {
          ::close(fd);
          return;
        }
        off += static_cast<std::size_t>(n);
      }
    }
    ::close(fd);
  });
  const long rss_before = rssKib();
  long rss_max = rss_before;
  std::size_t scans = 0, beams = 0, odometry = 0;
  LogReadStats stats;
  try {
    CarmenCallbacks cb;
    cb.on_scan = [&](LaserScan&& s) {
      ++scans;
      beams += s.ranges.size();
      if (scans % 1000 == 0) rss_max = std::max(rss_max, rssKib());
    };
    cb.on_odometry = [&](const StampedPose&) { ++odometry; };
    stats = forEachCarmenRecord(fifo, cb);
  } catch (...) {
    writer.join();
    throw;
  }
  writer.join();
  const long growth_kib = rss_max - rss_before;
  EXPECT_EQ(scans, blocks * 64);
  EXPECT_EQ(odometry, blocks * 64);
  EXPECT_EQ(beams, scans * 361);
  EXPECT_EQ(stats.repeated_timestamps, scans - 1);
  // Bounded: the line buffer, the scan being handed over and zlib's buffers; far below the log.
  EXPECT_LT(growth_kib, 32 * 1024) << "RSS grew by " << growth_kib << " KiB";
  std::printf("[ streamed %.0f MiB (%zu scans) through a FIFO; RSS growth at most %ld KiB ]\n",
              static_cast<double>(blocks * block.size()) / (1 << 20), scans, growth_kib);
}

// ---------------------------------------------------------------------------------------------
// TUM trajectories

TEST(HostileTum, NonFiniteValuesAndShortLinesAreErrors) {
  TempDir dir;
  expectErrorWith([&] { readTum(dir.write("a.tum", "1 nan 0 0 0 0 0 1\n")); }, "not finite");
  expectErrorWith([&] { readTum(dir.write("b.tum", "1 1e400 0 0 0 0 0 1\n")); }, "");
  EXPECT_THROW(readTum(dir.write("c.tum", "1 2 3\n")), Error);
  EXPECT_THROW(readTum(dir.write("d.tum", "1 0 0 0 0 0 0 0\n")), Error);  // zero quaternion
}

// ---------------------------------------------------------------------------------------------
// Floorplans and the ray caster built on them

TEST(HostileFloorplan, ZeroLengthDuplicateOverlappingAndEnormousSegments) {
  TempDir dir;
  const std::vector<std::array<double, 4>> segs = {
      {0, 0, 10, 0},          {0, 0, 10, 0},  // duplicate
      {2, 0, 8, 0},           {5, 0, 12, 0},  // overlapping the first, collinear
      {3, 3, 3, 3},                           // zero length
      {0, 5, 10, 5},          {10, 5, 0, 5},  // the same pane drawn both ways
      {-1e9, -1e9, 1e9, 1e9},                 // enormous diagonal (2.8e9 m)
      {-1e9, 7, 1e9, 7},                      // enormous horizontal
  };
  const auto path = dir.write("hostile.geojson", geojsonLines(segs));
  const VectorMap map = readFloorplan(path);
  ASSERT_GE(map.segments.size(), 8u);  // a reader may drop the zero-length one, never invent
  ASSERT_LE(map.segments.size(), segs.size());
  const RayCaster caster(map);
  // The index stays small however large the box: at most 2048 cells along the longer side.
  EXPECT_LE(static_cast<double>(caster.cellsX()) * caster.cellsY(), 2049.0 * 2049.0);
  EXPECT_LT(caster.cellEntries(), 100'000u);
  // The grid walk agrees with testing every segment, including through the huge cells.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> pos(-20.0, 20.0), ang(-3.2, 3.2);
  for (int i = 0; i < 2000; ++i) {
    const Vec2 o(pos(rng), pos(rng));
    const double a = ang(rng);
    const RayHit g = caster.cast(o, a, 1e10), b = caster.castBruteForce(o, a, 1e10);
    ASSERT_EQ(g.segment, b.segment) << "ray " << i;
    ASSERT_EQ(g.range, b.range) << "ray " << i;
  }
}

MapSegment seg(const Vec2& a, const Vec2& b, Material m) {
  MapSegment s;
  s.a = a;
  s.b = b;
  s.material = m;
  return s;
}

// Many enormous diagonal segments: building the index used to test every cell of each segment's
// bounding box (4M boxes per segment, hours for a few thousand); it must stay proportional to the
// cells the segments cross.
TEST(HostileFloorplan, ThousandsOfEnormousDiagonalSegmentsBuildQuickly) {
  VectorMap map;
  const int n = kSanitized ? 500 : 3000;
  for (int i = 0; i < n; ++i) {
    const double d = 1e6 * i;
    map.segments.push_back(seg(Vec2(-1e9 + d, -1e9), Vec2(1e9 + d, 1e9), Material::Wall));
  }
  // A 1 m cell request is clamped to extent / 2048: the finest grid the index allows (~4M cells).
  RayCasterOptions fine;
  fine.cell_size = 1.0;
  const RayCaster caster(map, fine);
  EXPECT_GE(caster.cellsX(), 2048);
  EXPECT_LE(static_cast<double>(caster.cellsX()) * caster.cellsY(), 2049.0 * 2049.0);
  // Each diagonal crosses ~2 * 2048 cells (+ eps-widened neighbours), far from 4M.
  EXPECT_LT(caster.cellEntries(), static_cast<std::size_t>(n) * 4 * 2100);
  const RayHit h = caster.cast(Vec2(0.0, 5.0), 0.0, 1e10);
  const RayHit b = caster.castBruteForce(Vec2(0.0, 5.0), 0.0, 1e10);
  EXPECT_EQ(h.segment, b.segment);
  EXPECT_TRUE(h.hit());
}

TEST(HostileFloorplan, NonFiniteOrOverflowingCoordinatesInAVectorMap) {
  VectorMap map;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  map.segments.push_back(seg(Vec2(0, 0), Vec2(10, 0), Material::Wall));
  map.segments.push_back(seg(Vec2(nan, 0), Vec2(10, 5), Material::Glass));
  map.segments.push_back(seg(Vec2(0, inf), Vec2(10, 5), Material::Glass));
  const RayCaster caster(map);  // the bad segments are never hit, the good one is
  const RayHit h = caster.cast(Vec2(5, 3), -kPi / 2, 100.0);
  EXPECT_EQ(h.segment, 0);
  EXPECT_DOUBLE_EQ(h.range, 3.0);
  // Finite coordinates whose extent overflows a double: a clear error, not a NaN-sized grid.
  VectorMap wide;
  wide.segments.push_back(seg(Vec2(-1.7e308, 0), Vec2(1.7e308, 1), Material::Wall));
  expectErrorWith([&] { RayCaster c(wide); }, "overflows");
  // The floorplan reader refuses non-finite coordinates with a clear error.
  TempDir dir;
  const auto p = dir.write("inf.geojson", R"({"type":"FeatureCollection","features":[{"type":"Feature",)"
                                          R"("properties":{},"geometry":{"type":"LineString",)"
                                          R"("coordinates":[[0,0],[1e400,0]]}}]})");
  EXPECT_THROW(readFloorplan(p), Error);
}

// Eight DXF files (5 B to 2.5 KB) found by fuzzing on which GDAL 3.6's DXF driver loops for
// minutes (misaligned group codes, a section never closed, no closing EOF, ENDTAB without TABLE,
// NUL bytes in the header, a damaged binary DXF, content after EOF, a final bare CR): refused up
// front.
TEST(HostileFloorplan, MalformedDxfThatHangsGdalIsRefusedQuickly) {
  const fs::path seeds = fs::path(GLASSMAP_SOURCE_DIR) / "tests" / "data" / "fuzz" / "fuzz_floorplan_dxf";
  expectErrorWith([&] { readFloorplan(seeds / "hang-misaligned-codes.dxf"); }, "group code");
  expectErrorWith([&] { readFloorplan(seeds / "hang-unclosed-section.dxf"); }, "SECTION inside");
  // This one also ends in a bare CR (refused first); without it, the missing EOF is the finding.
  expectErrorWith([&] { readFloorplan(seeds / "hang-no-eof.dxf"); }, "carriage return");
  TempDir no_eof_dir;
  std::string no_eof = readBytes(seeds / "hang-no-eof.dxf");
  no_eof.back() = '\n';
  expectErrorWith([&] { readFloorplan(no_eof_dir.write("no-eof.dxf", no_eof)); }, "no '0 EOF'");
  // This one also holds NUL bytes (refused first); without them its ENDTAB is the finding.
  expectErrorWith([&] { readFloorplan(seeds / "hang-endtab-without-table.dxf"); }, "NUL byte");
  TempDir dir;
  std::string endtab = readBytes(seeds / "hang-endtab-without-table.dxf");
  std::replace(endtab.begin(), endtab.end(), '\0', 'x');
  expectErrorWith([&] { readFloorplan(dir.write("endtab.dxf", endtab)); }, "ENDTAB without");
  expectErrorWith([&] { readFloorplan(seeds / "hang-nul-byte.dxf"); }, "NUL byte");
  expectErrorWith([&] { readFloorplan(seeds / "hang-binary.dxf"); }, "binary DXF");
  expectErrorWith([&] { readFloorplan(seeds / "hang-after-eof.dxf"); }, "after the closing");
  expectErrorWith([&] { readFloorplan(seeds / "hang-final-cr.dxf"); }, "carriage return");
  // Well-formed DXF (GDAL's own output, and a minimal hand-written one) still reads.
  EXPECT_EQ(readFloorplan(seeds / "tiny.dxf").segments.size(), 3u);
  EXPECT_EQ(readFloorplan(seeds / "minimal.dxf").segments.size(), 4u);
}

// ---------------------------------------------------------------------------------------------
// ROS maps and label rasters

TEST(HostileRosMap, MissingImageIsAnErrorNamingIt) {
  TempDir dir;
  const auto yaml = dir.write("map.yaml",
                              "image: nowhere.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n"
                              "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n");
  expectErrorWith([&] { readRosMap(yaml); }, "nowhere.pgm");
}

// Found by fuzzing: an image name longer than the system allows made the existence check throw a
// std::filesystem error past the reader. It is a clear error now, here and for the other readers.
TEST(HostileRosMap, ImageNameTooLongIsAnErrorNotAnEscapedException) {
  TempDir dir;
  const std::string name(5000, 'm');
  const auto yaml = dir.write("map.yaml", "image: " + name +
                                              ".pgm\nresolution: 0.05\norigin: [0, 0, 0]\n"
                                              "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n");
  expectErrorWith([&] { readRosMap(yaml); }, "does not exist");
  expectErrorWith([&] { readRosMap(dir / (name + ".yaml")); }, "does not exist");
  expectErrorWith([&] { readFloorplan(dir / (name + ".geojson")); }, "does not exist");
  expectErrorWith([&] { readLabelRaster(dir / (name + ".tif")); }, "no such file");
}

TEST(HostileRosMap, ForgedImageSizeIsRefusedBeforeAllocating) {
  TempDir dir;
  const auto yaml = dir.write("map.yaml",
                              "image: map.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n"
                              "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n");
  // 100000 x 100000 declared (10 GB), 4 bytes present.
  dir.write("map.pgm", std::string("P5\n100000 100000\n255\n") + std::string(4, '\0'));
  expectErrorWith([&] { readRosMap(yaml); }, "truncated");
  dir.write("map.pgm", "P2\n99999 99999\n255\n0 0 0\n");
  expectErrorWith([&] { readRosMap(yaml); }, "truncated");
}

/// Writes a GeoTIFF with GDAL: `bands` bands of `type`, a square-pixel geotransform.
void writeGeoTiff(const fs::path& p, int bands, GDALDataType type, bool rotated = false) {
  GDALAllRegister();
  GDALDriverH drv = GDALGetDriverByName("GTiff");
  GDALDatasetH ds = GDALCreate(drv, p.c_str(), 4, 3, bands, type, nullptr);
  ASSERT_NE(ds, nullptr);
  double gt[6] = {0.0, 0.05, rotated ? 0.01 : 0.0, 0.15, 0.0, -0.05};
  GDALSetGeoTransform(ds, gt);
  GDALClose(ds);
}

TEST(HostileLabels, GeoTiffOfTheWrongTypeIsAClearError) {
  TempDir dir;
  writeGeoTiff(dir / "float.tif", 1, GDT_Float32);
  expectErrorWith([&] { readLabelRaster(dir / "float.tif"); }, "Byte");
  writeGeoTiff(dir / "rgb.tif", 3, GDT_Byte);
  expectErrorWith([&] { readLabelRaster(dir / "rgb.tif"); }, "single-band");
  writeGeoTiff(dir / "rot.tif", 1, GDT_Byte, /*rotated=*/true);
  expectErrorWith([&] { readLabelRaster(dir / "rot.tif"); }, "unrotated");
  dir.write("text.tif", "not a tiff at all\n");
  EXPECT_THROW(readLabelRaster(dir / "text.tif"), Error);
  expectErrorWith([&] { readLabelRaster(dir / "missing.tif"); }, "missing.tif");
  // The right type still reads.
  writeGeoTiff(dir / "ok.tif", 1, GDT_Byte);
  const LabelRaster r = readLabelRaster(dir / "ok.tif");
  EXPECT_EQ(r.width, 4);
  EXPECT_EQ(r.height, 3);
}

}  // namespace
}  // namespace glassmap
