// ScanSpool and forEachScanBlock: scans kept on disk come back bit for bit, block by block, with
// the changes a log in memory gets in place (a re-centred frame, the no-return code).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>
#include <random>

#include "glassmap/core/error.hpp"
#include "glassmap/core/laser_scan.hpp"
#include "glassmap/core/scan_spool.hpp"

namespace glassmap {
namespace {

namespace fs = std::filesystem;

// An empty folder of this test's own.
fs::path freshFolder(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("glassmap-spool-" + std::to_string(::getpid()) + "-" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// Scans of every shape: beam counts 0 to 400, no-returns, far poses, both odometry flags, two lasers.
LaserLog variedLog(int n) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  LaserLog log;
  for (int k = 0; k < n; ++k) {
    LaserScan s;
    s.timestamp = 1e9 + 0.1 * k + 1e-7 * u(rng);
    s.start_angle = -M_PI / 2 + 1e-3 * u(rng);
    s.angular_step = M_PI / 360.0;
    s.max_range = k % 3 == 0 ? 0.0 : 30.0;
    s.laser_pose = Pose2(5e5 + 100 * u(rng), 5.4e6 + 100 * u(rng), M_PI * u(rng));
    s.odom_pose = Pose2(u(rng), u(rng), u(rng));
    s.has_odom = k % 2 == 0;
    s.has_laser_pose = k % 5 != 0;
    s.laser_id = 1 + k % 2;
    const int beams = (k * 37) % 401;
    for (int i = 0; i < beams; ++i)
      s.ranges.push_back(i % 17 == 0 ? kNoReturn : (i % 23 == 0 ? 50.0f : static_cast<float>(15.0 + 15.0 * u(rng))));
    log.scans.push_back(s);
  }
  return log;
}

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void expectSameScan(const LaserScan& a, const LaserScan& b) {
  EXPECT_TRUE(sameBits(a.timestamp, b.timestamp));
  EXPECT_TRUE(sameBits(a.start_angle, b.start_angle));
  EXPECT_TRUE(sameBits(a.angular_step, b.angular_step));
  EXPECT_TRUE(sameBits(a.max_range, b.max_range));
  EXPECT_TRUE(sameBits(a.laser_pose.x(), b.laser_pose.x()));
  EXPECT_TRUE(sameBits(a.laser_pose.y(), b.laser_pose.y()));
  EXPECT_TRUE(sameBits(a.laser_pose.theta, b.laser_pose.theta));
  EXPECT_TRUE(sameBits(a.odom_pose.x(), b.odom_pose.x()));
  EXPECT_TRUE(sameBits(a.odom_pose.theta, b.odom_pose.theta));
  EXPECT_EQ(a.has_odom, b.has_odom);
  EXPECT_EQ(a.has_laser_pose, b.has_laser_pose);
  EXPECT_EQ(a.laser_id, b.laser_id);
  ASSERT_EQ(a.ranges.size(), b.ranges.size());
  if (!a.ranges.empty()) {
    EXPECT_EQ(std::memcmp(a.ranges.data(), b.ranges.data(), a.ranges.size() * sizeof(float)), 0);
  }
}

// The log's scans on disk, read back in blocks of about `block_bytes`.
LaserLog spooled(const LaserLog& log, const fs::path& dir, std::size_t block_bytes) {
  auto spool = std::make_shared<ScanSpool>(dir);
  for (const LaserScan& s : log.scans) spool->append(s);
  spool->flush();
  LaserLog out;
  out.spooled = SpooledScans{spool, Vec2::Zero(), {}, block_bytes};
  return out;
}

std::vector<LaserScan> allScans(const LaserLog& log) {
  std::vector<LaserScan> out;
  forEachScanBlock(log, [&](std::span<const LaserScan> block, std::size_t first) {
    EXPECT_EQ(first, out.size());  // blocks in order, none skipped
    out.insert(out.end(), block.begin(), block.end());
  });
  return out;
}

TEST(ScanSpool, ScansComeBackBitForBitInOrderAcrossBlocks) {
  const fs::path dir = freshFolder("roundtrip");
  const LaserLog log = variedLog(300);
  for (std::size_t block : {std::size_t{1}, std::size_t{20000}, std::size_t{1} << 30}) {
    const LaserLog disk = spooled(log, dir, block);
    EXPECT_EQ(disk.scanCount(), log.scans.size());
    EXPECT_TRUE(disk.scans.empty());
    std::size_t blocks = 0;
    forEachScanBlock(disk, [&](std::span<const LaserScan>, std::size_t) { ++blocks; });
    if (block == 1) {
      EXPECT_EQ(blocks, log.scans.size());  // one scan per block at least
    } else if (block == 20000) {
      EXPECT_GT(blocks, 10u);
    } else {
      EXPECT_EQ(blocks, 1u);
    }
    const std::vector<LaserScan> back = allScans(disk);
    ASSERT_EQ(back.size(), log.scans.size());
    for (std::size_t i = 0; i < back.size(); ++i) expectSameScan(back[i], log.scans[i]);
  }
  // The file is unnamed: nothing of it is in the folder, during or after.
  EXPECT_TRUE(fs::is_empty(dir));
  fs::remove_all(dir);
}

TEST(ScanSpool, PassesSeeWhatTheLogInMemoryHoldsAfterShiftAndNoReturnCode) {
  const fs::path dir = freshFolder("shift");
  LaserLog memory = variedLog(200);
  LaserLog disk = spooled(memory, dir, 30000);
  // The reader's no-return code (50 m readings at many beams) and a re-centred frame.
  EXPECT_TRUE(markMaxRangeCode(memory));
  EXPECT_TRUE(markMaxRangeCode(disk));
  EXPECT_EQ(disk.stats.max_range_code, memory.stats.max_range_code);
  EXPECT_EQ(disk.stats.max_range_code_readings, memory.stats.max_range_code_readings);
  const Vec2 shift(5e5, 5.4e6);
  for (LaserScan& s : memory.scans) s.laser_pose.t -= shift;
  disk.spooled->shift = shift;
  const std::vector<LaserScan> back = allScans(disk);
  ASSERT_EQ(back.size(), memory.scans.size());
  for (std::size_t i = 0; i < back.size(); ++i) expectSameScan(back[i], memory.scans[i]);
  EXPECT_LT(memory.scans[1].max_range, 50.0);  // the code became the maximum
  fs::remove_all(dir);
}

TEST(ScanSpool, BorrowedScansAreCopiedOutBlockByBlockWithTheShift) {
  LaserLog memory = variedLog(120);
  LaserLog view;
  view.spooled = SpooledScans{borrowScans(memory.scans), Vec2(5e5, 5.4e6), {}, 10000};
  EXPECT_EQ(view.scanCount(), memory.scans.size());
  EXPECT_LT(view.memoryBytes(), memory.memoryBytes());
  std::size_t blocks = 0;
  forEachScanBlock(view, [&](std::span<const LaserScan>, std::size_t) { ++blocks; });
  EXPECT_GT(blocks, 5u);
  const std::vector<LaserScan> back = allScans(view);
  for (LaserScan& s : memory.scans) s.laser_pose.t -= Vec2(5e5, 5.4e6);
  ASSERT_EQ(back.size(), memory.scans.size());
  for (std::size_t i = 0; i < back.size(); ++i) expectSameScan(back[i], memory.scans[i]);
}

TEST(ScanSpool, AFolderThatCannotHoldItIsAnErrorNamingIt) {
  const fs::path missing = fs::temp_directory_path() / "glassmap-no-such-folder" / "deeper";
  try {
    ScanSpool spool(missing);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.file(), missing.string());
    EXPECT_NE(e.message().find("temporary file"), std::string::npos) << e.message();
  }
}

TEST(ScanSpool, MemoryCountsTheBlocksNotTheScans) {
  const fs::path dir = freshFolder("memory");
  const LaserLog memory = variedLog(300);
  const LaserLog disk = spooled(memory, dir, 1u << 16);
  EXPECT_EQ(disk.memoryBytes(), 2u * (1u << 16));
  EXPECT_GT(memory.memoryBytes(), disk.memoryBytes());
  fs::remove_all(dir);
}

}  // namespace
}  // namespace glassmap
