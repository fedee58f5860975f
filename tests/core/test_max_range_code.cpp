// markMaxRangeCode: a spike of identical readings at the very top of a laser's readings is its
// "no return" value; spread-out top readings are not.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "glassmap/core/laser_scan.hpp"

namespace glassmap {
namespace {

// 100 scans of 180 readings uniform in [0.5, 20] m, `coded` of them per scan (beams 0.. in the
// first scan, shifted by 37 beams from scan to scan) replaced by `code`.
LaserLog logWithCode(float code, int coded, double header_max, int laser_id = 1) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> range(0.5f, 20.0f);
  LaserLog log;
  for (int k = 0; k < 100; ++k) {
    LaserScan s;
    s.laser_id = laser_id;
    s.max_range = header_max;
    for (int i = 0; i < 180; ++i) s.ranges.push_back((i + 37 * k) % 180 < coded ? code : range(rng));
    log.scans.push_back(s);
  }
  return log;
}

TEST(MaxRangeCode, BelowTheHeaderMaximumItBecomesTheMaximum) {
  LaserLog log = logWithCode(50.0f, 2, 80.0);  // ACES: 50 m readings, CARMEN's guess 80 m
  ASSERT_TRUE(log.scans[0].isReturn(0));
  EXPECT_TRUE(markMaxRangeCode(log));
  EXPECT_DOUBLE_EQ(log.stats.max_range_code, 50.0);
  EXPECT_EQ(log.stats.max_range_code_readings, 200u);
  EXPECT_NEAR(log.scans[0].max_range, 49.995, 1e-9);
  EXPECT_FALSE(log.scans[0].isReturn(0));  // the coded reading is a max reading now
  EXPECT_TRUE(log.scans[0].isReturn(5));   // ordinary readings stay returns
}

TEST(MaxRangeCode, AboveTheHeaderMaximumNothingChanges) {
  LaserLog log = logWithCode(81.91f, 3, 80.0);  // Freiburg: 81.91 m, already beyond the 80 m guess
  EXPECT_TRUE(markMaxRangeCode(log));
  EXPECT_NEAR(log.stats.max_range_code, 81.91, 1e-5);
  EXPECT_DOUBLE_EQ(log.scans[0].max_range, 80.0);
  EXPECT_FALSE(log.scans[0].isReturn(0));
}

TEST(MaxRangeCode, RareOrSpreadTopReadingsAreNoCode) {
  // One reading in 18,000 at the top: below 0.1%.
  LaserLog rare = logWithCode(50.0f, 0, 80.0);
  rare.scans[3].ranges[7] = 50.0f;
  rare.scans[4].ranges[7] = 50.0f;
  EXPECT_FALSE(markMaxRangeCode(rare));
  EXPECT_EQ(rare.stats.max_range_code, 0.0);
  EXPECT_TRUE(rare.scans[3].isReturn(7));
  // Uniform readings only: the top is one value.
  LaserLog plain = logWithCode(0.0f, 0, 80.0);
  EXPECT_FALSE(markMaxRangeCode(plain));
  for (const LaserScan& s : plain.scans) EXPECT_DOUBLE_EQ(s.max_range, 80.0);
}

TEST(MaxRangeCode, AFarCornerReadAgainAndAgainIsNoCode) {
  // A standing robot reads the same far corner (22.4 m) on beams 90 and 91 of every scan: 1.1%
  // of the readings, but at two beam indices only.
  LaserLog log = logWithCode(0.0f, 0, 80.0);
  for (LaserScan& s : log.scans) s.ranges[90] = s.ranges[91] = 22.4f;
  EXPECT_FALSE(markMaxRangeCode(log));
  EXPECT_TRUE(log.scans[0].isReturn(90));
}

TEST(MaxRangeCode, StreamingFinderAgreesAndKnowsTheLongestReturnBelow) {
  const LaserLog log = logWithCode(50.0f, 2, 80.0);
  MaxRangeCodeFinder finder;
  double longest = 0.0;
  for (const LaserScan& s : log.scans)
    for (std::size_t i = 0; i < s.ranges.size(); ++i) {
      finder.add(s.laser_id, s.ranges[i], i);
      if (s.ranges[i] < 49.0f) longest = std::max(longest, static_cast<double>(s.ranges[i]));
    }
  std::size_t n = 0;
  EXPECT_DOUBLE_EQ(finder.code(1, &n), 50.0);
  EXPECT_EQ(n, 200u);
  EXPECT_DOUBLE_EQ(finder.longestBelowCode(1), longest);
  EXPECT_EQ(finder.code(2), 0.0);  // a laser never seen
  LogReadStats stats;
  finder.record(stats);
  EXPECT_DOUBLE_EQ(stats.max_range_code, 50.0);
}

TEST(MaxRangeCode, EachLaserHasItsOwn) {
  LaserLog log = logWithCode(50.0f, 2, 80.0, 1);
  const LaserLog rear = logWithCode(0.0f, 0, 80.0, 2);  // no code on the rear laser
  log.scans.insert(log.scans.end(), rear.scans.begin(), rear.scans.end());
  EXPECT_TRUE(markMaxRangeCode(log));
  EXPECT_NEAR(log.scans.front().max_range, 49.995, 1e-9);
  EXPECT_DOUBLE_EQ(log.scans.back().max_range, 80.0);
}

}  // namespace
}  // namespace glassmap
