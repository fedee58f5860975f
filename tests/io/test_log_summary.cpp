#include <gtest/gtest.h>

#include "glassmap/core/angles.hpp"
#include "glassmap/io/carmen.hpp"
#include "glassmap/io/log_summary.hpp"
#include "io_test_util.hpp"

namespace glassmap {
namespace {

TEST(IoLogSummary, NoReturnCodeBelowTheGuessedMaximum) {
  // FLASER lines carry no maximum (80 m guessed); this scanner reports no return as 50 m, on
  // 20 beams of each scan (shifting from scan to scan). The summary and readCarmenLog agree.
  test::TempDir dir;
  std::string text;
  for (int k = 0; k < 10; ++k) {
    text += "FLASER 181";
    for (int i = 0; i < 181; ++i) text += (i + 13 * k) % 181 < 20 ? " 50.00" : " " + std::to_string(1.0 + 0.01 * i);
    text += " 0 0 0 0 0 0 " + std::to_string(k) + " h 0\n";
  }
  const auto p = dir.write("code.clf", text);
  const LogSummary s = summarizeCarmenLog(p);
  EXPECT_DOUBLE_EQ(s.stats.max_range_code, 50.0);
  EXPECT_EQ(s.stats.max_range_code_readings, 200u);
  EXPECT_EQ(s.max_readings, 200u);
  EXPECT_NEAR(s.longest_return, 2.8, 1e-5);
  const LaserLog log = readCarmenLog(p);
  EXPECT_DOUBLE_EQ(log.stats.max_range_code, 50.0);
  EXPECT_NEAR(log.scans[0].max_range, 49.995, 1e-9);
  EXPECT_FALSE(log.scans[0].isReturn(0));
  EXPECT_TRUE(log.scans[0].isReturn(100));
  CarmenReadOptions keep;
  keep.detect_max_range_code = false;
  EXPECT_TRUE(readCarmenLog(p, keep).scans[0].isReturn(0));
}

TEST(IoLogSummary, SyntheticFigures) {
  test::TempDir dir;
  // Three FLASER scans (181, 181, 361 beams) along x: 0 -> 3 -> 3 (then back in time once),
  // one ODOM at t=0.5 and one at t=20, a NEFF line, ranges with a no-return and a max reading.
  auto scan = [](int n, double x, double y, double t, const std::string& first) {
    std::string line = "FLASER " + std::to_string(n) + " " + first;
    for (int i = 1; i < n; ++i) line += " 2.5";
    line += " " + std::to_string(x) + " " + std::to_string(y) + " 0 0 0 0 " + std::to_string(t) + " h 0\n";
    return line;
  };
  const auto p =
      dir.write("s.clf", "ODOM 0 0 0 0 0 0 0.5 h 0\n" + scan(181, 0, 0, 1.0, "nan") + scan(181, 3, 0, 2.0, "80") +
                             "NEFF 3\n" + scan(361, 3, 4, 1.5, "1") + "ODOM 3 4 0 0 0 0 20 h 0\n");
  const LogSummary s = summarizeCarmenLog(p);
  EXPECT_EQ(s.scans, 3u);
  EXPECT_EQ(s.beams_min, 181u);
  EXPECT_EQ(s.beams_max, 361u);
  EXPECT_NEAR(rad2deg(s.fov_min), 180.0, 1e-9);
  EXPECT_NEAR(rad2deg(s.step_min), 0.5, 1e-12);
  EXPECT_NEAR(rad2deg(s.step_max), 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(s.max_range_max, 80.0);
  EXPECT_EQ(s.max_readings, 1u);
  EXPECT_DOUBLE_EQ(s.longest_return, 2.5);
  EXPECT_EQ(s.stats.no_return_ranges, 1u);
  EXPECT_DOUBLE_EQ(s.t_first, 0.5);
  EXPECT_DOUBLE_EQ(s.t_last, 20.0);
  EXPECT_DOUBLE_EQ(s.duration(), 19.5);
  EXPECT_EQ(s.time_reversals, 1u);
  EXPECT_DOUBLE_EQ(s.distance, 7.0);  // 3 along x, then 4 along y
  EXPECT_DOUBLE_EQ(s.odometry_distance, 5.0);
  EXPECT_EQ(s.pose_bounds.min(), Vec2(0, 0));
  EXPECT_EQ(s.pose_bounds.max(), Vec2(3, 4));
  EXPECT_EQ(s.stats.skipped_by_type.at("NEFF"), 1u);
  EXPECT_EQ(s.stats.odometry, 2u);
}

TEST(IoLogSummary, FreiburgIsPlausible) {
  const auto freiburg = test::realLog("freiburg-079-corrected.log.gz");
  GLASSMAP_REQUIRE_SHARED_DATA(freiburg);
  const LogSummary s = summarizeCarmenLog(freiburg);
  EXPECT_EQ(s.scans, 4791u);
  EXPECT_EQ(s.beams_min, 360u);
  EXPECT_EQ(s.beams_max, 360u);
  EXPECT_NEAR(rad2deg(s.fov_max), 179.5, 1e-9);
  EXPECT_DOUBLE_EQ(s.max_range_max, 80.99);
  // A building floor: tens of metres across, a walk of some hundred metres over some minutes.
  const Vec2 size = s.pose_bounds.max() - s.pose_bounds.min();
  EXPECT_GT(size.x(), 10.0);
  EXPECT_LT(size.x(), 100.0);
  EXPECT_GT(s.distance, 100.0);
  EXPECT_LT(s.distance, 2000.0);
  EXPECT_GT(s.duration(), 300.0);
  EXPECT_LT(s.duration(), 7200.0);
  EXPECT_EQ(s.stats.skipped_by_type.at("NEFF"), 4791u);
  EXPECT_EQ(s.stats.no_return_ranges, 0u);
}

}  // namespace
}  // namespace glassmap
