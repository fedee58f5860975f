#include <gtest/gtest.h>
#include <zlib.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <iterator>

#include "glassmap/core/angles.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/io/carmen.hpp"
#include "io_test_util.hpp"

namespace glassmap {
namespace {

using test::TempDir;

// A FLASER line with n beams all at `range`, pose (1, 2, 0.5), odometry (3, 4, -0.5).
std::string flaser(int declared, int actual, const std::string& range = "1.5", double t = 10.0) {
  std::string line = "FLASER " + std::to_string(declared);
  for (int i = 0; i < actual; ++i) line += " " + range;
  line += " 1 2 0.5 3 4 -0.5 " + std::to_string(t) + " host " + std::to_string(t) + "\n";
  return line;
}

std::string readFileBytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void expectSameLog(const LaserLog& a, const LaserLog& b) {
  ASSERT_EQ(a.scans.size(), b.scans.size());
  for (std::size_t i = 0; i < a.scans.size(); ++i) {
    const LaserScan& s = a.scans[i];
    const LaserScan& r = b.scans[i];
    SCOPED_TRACE("scan " + std::to_string(i));
    EXPECT_EQ(s.timestamp, r.timestamp);
    EXPECT_EQ(s.start_angle, r.start_angle);
    EXPECT_EQ(s.angular_step, r.angular_step);
    EXPECT_EQ(s.max_range, r.max_range);
    EXPECT_EQ(s.ranges, r.ranges);
    EXPECT_TRUE(approxEqual(s.laser_pose, r.laser_pose, 0.0, 0.0));
    EXPECT_TRUE(approxEqual(s.odom_pose, r.odom_pose, 0.0, 0.0));
    EXPECT_EQ(s.has_odom, r.has_odom);
    EXPECT_EQ(s.laser_id, r.laser_id);
  }
  ASSERT_EQ(a.odometry.size(), b.odometry.size());
  for (std::size_t i = 0; i < a.odometry.size(); ++i) {
    EXPECT_EQ(a.odometry[i].timestamp, b.odometry[i].timestamp);
    EXPECT_TRUE(approxEqual(a.odometry[i].pose, b.odometry[i].pose, 0.0, 0.0));
    EXPECT_EQ(a.odometry[i].tv, b.odometry[i].tv);
    EXPECT_EQ(a.odometry[i].rv, b.odometry[i].rv);
  }
  ASSERT_EQ(a.true_poses.size(), b.true_poses.size());
  for (std::size_t i = 0; i < a.true_poses.size(); ++i) {
    EXPECT_EQ(a.true_poses[i].timestamp, b.true_poses[i].timestamp);
    EXPECT_TRUE(approxEqual(a.true_poses[i].pose, b.true_poses[i].pose, 0.0, 0.0));
  }
  EXPECT_EQ(a.params, b.params);
}

/// Expects readCarmenLog(path) to throw an Error whose text holds each of `parts`.
void expectReadError(const std::filesystem::path& path, std::initializer_list<std::string> parts,
                     std::size_t line = 0) {
  try {
    readCarmenLog(path);
    ADD_FAILURE() << "no error for " << path;
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.file(), path.string()) << what;
    if (line) {
      EXPECT_EQ(e.line(), line) << what;
    }
    for (const auto& p : parts) EXPECT_NE(what.find(p), std::string::npos) << "'" << p << "' not in: " << what;
  }
}

struct RealLog {
  const char* file;
  std::size_t scans, beams, odometry;
  double step_deg, fov_deg;
};

void PrintTo(const RealLog& p, std::ostream* os) { *os << p.file; }

class CarmenRealLogs : public ::testing::TestWithParam<RealLog> {};

TEST_P(CarmenRealLogs, ParseWithRightCounts) {
  const RealLog& p = GetParam();
  const auto path = test::realLog(p.file);
  GLASSMAP_REQUIRE_SHARED_DATA(path);
  const LaserLog log = readCarmenLog(path);
  EXPECT_EQ(log.scans.size(), p.scans);
  EXPECT_EQ(log.stats.scans, p.scans);
  EXPECT_EQ(log.odometry.size(), p.odometry);
  EXPECT_EQ(log.stats.skipped_by_type.at("NEFF"), p.scans);  // one NEFF line per scan, skipped
  EXPECT_EQ(log.stats.comment_lines, 2u);
  for (const LaserScan& s : log.scans) {
    ASSERT_EQ(s.ranges.size(), p.beams);
    EXPECT_EQ(s.laser_id, 1);
    EXPECT_TRUE(s.has_odom);
    EXPECT_DOUBLE_EQ(s.start_angle, -0.5 * kPi);
    EXPECT_NEAR(rad2deg(s.angular_step), p.step_deg, 1e-12);
    EXPECT_NEAR(rad2deg(s.fieldOfView()), p.fov_deg, 1e-9);
  }
  // (Timestamps are not monotonic in every real log: intel steps back four times.)
}

INSTANTIATE_TEST_SUITE_P(Io, CarmenRealLogs,
                         ::testing::Values(RealLog{"intel-corrected.log.gz", 910, 180, 14541, 1.0, 179.0},
                                           RealLog{"freiburg-079-corrected.log.gz", 4791, 360, 9725, 0.5, 179.5},
                                           RealLog{"aces-corrected.log.gz", 440, 180, 7814, 1.0, 179.0}),
                         [](const auto& info) {
                           std::string n = info.param.file;
                           n = n.substr(0, n.find('-'));
                           return n;
                         });

TEST(Carmen, FreiburgMaxRangeFromParam) {
  const auto freiburg = test::realLog("freiburg-079-corrected.log.gz");
  const auto intel_path = test::realLog("intel-corrected.log.gz");
  GLASSMAP_REQUIRE_SHARED_DATA(freiburg);
  GLASSMAP_REQUIRE_SHARED_DATA(intel_path);
  const LaserLog log = readCarmenLog(freiburg);
  EXPECT_EQ(log.params.at("robot_front_laser_max"), "80.99");
  EXPECT_DOUBLE_EQ(log.scans.front().max_range, 80.99);
  const LaserLog intel = readCarmenLog(intel_path);
  EXPECT_DOUBLE_EQ(intel.scans.front().max_range, 80.0);  // no PARAM: CARMEN's own guess
}

TEST(Carmen, RealLogRoundTrip) {
  TempDir dir;
  const auto intel = test::realLog("intel-corrected.log.gz");
  GLASSMAP_REQUIRE_SHARED_DATA(intel);
  const LaserLog log = readCarmenLog(intel);
  for (const char* name : {"intel.clf", "intel.clf.gz"}) {
    writeCarmenLog(dir / name, log);
    const LaserLog back = readCarmenLog(dir / name);
    expectSameLog(log, back);
  }
  // .gz output is really compressed, .clf is plain text.
  EXPECT_EQ(readFileBytes(dir / "intel.clf.gz").substr(0, 2), std::string("\x1f\x8b"));
  EXPECT_EQ(readFileBytes(dir / "intel.clf").substr(0, 1), "#");
}

TEST(Carmen, ALogOverTheSpoolLimitIsKeptOnDiskAndReadsBackTheSame) {
  TempDir dir;
  const auto aces = test::realLog("aces-corrected.log.gz");  // has a no-return code (50 m readings)
  GLASSMAP_REQUIRE_SHARED_DATA(aces);
  const LaserLog memory = readCarmenLog(aces);
  ASSERT_GT(memory.stats.max_range_code, 0.0);
  CarmenReadOptions o;
  o.spool_directory = dir.path();
  o.spool_above_bytes = 100000;  // the log holds about 0.4 MB
  o.max_memory_bytes = 200000;   // the scans on disk do not count
  const LaserLog disk = readCarmenLog(aces, o);
  ASSERT_TRUE(disk.spooled.has_value());
  EXPECT_TRUE(disk.scans.empty());
  EXPECT_EQ(disk.scanCount(), memory.scans.size());
  EXPECT_EQ(disk.stats.max_range_code, memory.stats.max_range_code);
  EXPECT_EQ(disk.odometry.size(), memory.odometry.size());
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));  // an unnamed file
  LaserLog back;
  back.odometry = disk.odometry;
  back.params = disk.params;
  forEachScanBlock(disk, [&](std::span<const LaserScan> b, std::size_t) {
    back.scans.insert(back.scans.end(), b.begin(), b.end());
  });
  expectSameLog(memory, back);  // the code applied to the spooled scans too
  // Under the limit, the log stays in memory.
  o.spool_above_bytes = 1u << 30;
  o.max_memory_bytes = 0;
  EXPECT_FALSE(readCarmenLog(aces, o).spooled.has_value());
}

TEST(Carmen, SyntheticRoundTripKeepsEveryField) {
  TempDir dir;
  LaserLog log;
  for (int i = 0; i < 5; ++i) {
    LaserScan s;
    s.timestamp = 1071078718.462310 + 0.1 * i;
    s.start_angle = -2.0943951023931953;
    s.angular_step = 0.0061359231515425647;
    s.max_range = 29.5;
    s.ranges = {0.1f, 1.23456789f, kNoReturn, 29.5f, 12.0f / 7.0f};
    s.ranges.resize(static_cast<std::size_t>(50 + i), 3.25f);  // beam count varies
    s.laser_pose = Pose2(1.0 / 3.0, -2.0 / 7.0, 3.0);
    s.odom_pose = Pose2(10.125, -4e-7, -3.1);
    s.has_odom = i != 3;
    s.laser_id = i == 4 ? 2 : 1;
    log.scans.push_back(s);
    StampedPose o;
    o.timestamp = s.timestamp - 0.05;
    o.pose = Pose2(0.1 * i, 0.2, 0.3);
    o.tv = 0.25;
    o.rv = -0.125;
    log.odometry.push_back(o);
    StampedPose t;
    t.timestamp = s.timestamp + 0.01;
    t.pose = Pose2(1e-9 * i, 5.0, -1.0);
    log.true_poses.push_back(t);
  }
  log.params["robot_front_laser_max"] = "29.5";
  log.params["note"] = "glass";
  writeCarmenLog(dir / "synthetic.clf", log);
  LaserLog back = readCarmenLog(dir / "synthetic.clf");
  // A scan without odometry is written with its laser pose as the robot pose.
  log.scans[3].has_odom = true;
  log.scans[3].odom_pose = log.scans[3].laser_pose;
  expectSameLog(log, back);
  EXPECT_EQ(back.stats.no_return_ranges, 5u);
  EXPECT_EQ(back.stats.true_poses, 5u);
}

TEST(Carmen, RobotLaserWithAndWithoutRemissions) {
  TempDir dir;
  const std::string with =
      "ROBOTLASER1 0 -1.5 3.0 0.5 20 0.01 0 7 1 2 3 4 5 6 7 3 100 200 300 "
      "1 2 0.5 1.1 2.1 0.6 0 0 0 0 0 100.5 host 100.5\n";
  const std::string without =
      "ROBOTLASER1 0 -1.5 3.0 0.5 20 0.01 0 7 1 2 3 4 5 6 7 "
      "1 2 0.5 1.1 2.1 0.6 0 0 0 0 0 101.5 host 101.5\n";
  const LaserLog log = readCarmenLog(dir.write("r.clf", with + without));
  ASSERT_EQ(log.scans.size(), 2u);
  for (const LaserScan& s : log.scans) {
    EXPECT_EQ(s.ranges.size(), 7u);
    EXPECT_EQ(s.ranges[6], 7.0f);
    EXPECT_DOUBLE_EQ(s.start_angle, -1.5);
    EXPECT_DOUBLE_EQ(s.angular_step, 0.5);
    EXPECT_DOUBLE_EQ(s.max_range, 20.0);
    EXPECT_DOUBLE_EQ(s.laser_pose.x(), 1.0);
    EXPECT_DOUBLE_EQ(s.odom_pose.theta, 0.6);
  }
  EXPECT_DOUBLE_EQ(log.scans[1].timestamp, 101.5);
}

TEST(Carmen, RawLaserOdomTruePosParamAndUnknownLines) {
  TempDir dir;
  const std::string text =
      "# comment\n\n"
      "PARAM robot_use_laser on nohost 0\n"
      "ODOM 1 2 0.1 0.3 0.05 0 5.0 host 5.0\n"
      "RAWLASER3 0 -1.0 2.0 0 30 0.01 0 5 1 2 3 4 5 0 6.0 host 6.0\n"
      "TRUEPOS 7 8 0.2 1 2 0.1 6.5 host 6.5\n"
      "NEFF 12\nSYNC a b\nNEFF 3\n";
  const LaserLog log = readCarmenLog(dir.write("m.clf", text));
  ASSERT_EQ(log.scans.size(), 1u);
  const LaserScan& s = log.scans[0];
  EXPECT_EQ(s.laser_id, 3);
  EXPECT_FALSE(s.has_laser_pose);
  EXPECT_FALSE(s.has_odom);
  EXPECT_DOUBLE_EQ(s.angular_step, 0.5);  // 0 in the line: fov / (n - 1)
  ASSERT_EQ(log.odometry.size(), 1u);
  EXPECT_DOUBLE_EQ(log.odometry[0].tv, 0.3);
  EXPECT_DOUBLE_EQ(log.odometry[0].timestamp, 5.0);
  ASSERT_EQ(log.true_poses.size(), 1u);
  EXPECT_DOUBLE_EQ(log.true_poses[0].pose.x(), 7.0);
  EXPECT_EQ(log.params.at("robot_use_laser"), "on");
  EXPECT_EQ(log.stats.skipped_lines, 3u);
  EXPECT_EQ(log.stats.skipped_by_type.at("NEFF"), 2u);
  EXPECT_EQ(log.stats.skipped_by_type.at("SYNC"), 1u);
  EXPECT_EQ(log.stats.comment_lines, 2u);
  EXPECT_EQ(log.stats.lines, 9u);
}

TEST(Carmen, LaserIdOptionFilters) {
  TempDir dir;
  const auto p = dir.write("two.clf", flaser(3, 3) + "RLASER 3 1 1 1 0 0 0 0 0 0 11 h 11\n");
  CarmenReadOptions opt;
  opt.laser_id = 2;
  const LaserLog log = readCarmenLog(p, opt);
  ASSERT_EQ(log.scans.size(), 1u);
  EXPECT_EQ(log.scans[0].laser_id, 2);
  EXPECT_EQ(log.stats.filtered_scans, 1u);
}

TEST(Carmen, FlaserFovGuessMatchesCarmen) {
  EXPECT_DOUBLE_EQ(carmenGuessFov(181), kPi);
  EXPECT_DOUBLE_EQ(carmenGuessFov(361), kPi);
  EXPECT_DOUBLE_EQ(carmenGuessFov(180), deg2rad(179.0));
  EXPECT_DOUBLE_EQ(carmenGuessFov(360), deg2rad(179.5));
  EXPECT_DOUBLE_EQ(carmenGuessAngleIncrement(181), deg2rad(1.0));
  EXPECT_DOUBLE_EQ(carmenGuessAngleIncrement(361), deg2rad(0.5));
  EXPECT_DOUBLE_EQ(carmenGuessAngleIncrement(401), deg2rad(0.25));
  EXPECT_DOUBLE_EQ(carmenGuessAngleIncrement(91), kPi / 90.0);
  TempDir dir;
  const LaserLog log = readCarmenLog(dir.write("f.clf", flaser(181, 181)));
  EXPECT_NEAR(rad2deg(log.scans[0].fieldOfView()), 180.0, 1e-9);
  EXPECT_DOUBLE_EQ(log.scans[0].start_angle, -0.5 * kPi);
}

TEST(Carmen, NonFiniteAndNegativeRangesBecomeNoReturn) {
  TempDir dir;
  std::string line = "FLASER 6 1.0 nan inf -inf -2.5 3.0 1 2 0.5 3 4 -0.5 10 host 10\n";
  const LaserLog log = readCarmenLog(dir.write("nan.clf", line));
  ASSERT_EQ(log.scans.size(), 1u);
  const auto& r = log.scans[0].ranges;
  EXPECT_EQ(r[0], 1.0f);
  for (int i = 1; i <= 4; ++i) EXPECT_EQ(r[static_cast<std::size_t>(i)], kNoReturn);
  EXPECT_EQ(r[5], 3.0f);
  EXPECT_FALSE(log.scans[0].isReturn(1));
  EXPECT_EQ(log.stats.no_return_ranges, 4u);
}

TEST(Carmen, TruncatedLineNamesLineAndField) {
  TempDir dir;
  const auto p = dir.write("trunc.clf", flaser(5, 5) + "FLASER 5 1.0 2.0 3.0\n");
  expectReadError(p, {"num_readings", "truncated", "5 ranges"}, 2);
}

TEST(Carmen, LettersInANumberNameTheField) {
  TempDir dir;
  const auto p = dir.write("letters.clf", "# c\nFLASER 5 1.0 2.0 3.0 4x 5.0 1 2 0.5 3 4 -0.5 10 host 10\n");
  expectReadError(p, {"range[3]", "'4x'", "expected a number"}, 2);
  const auto q = dir.write("odom.clf", "ODOM 1 2 0.1 0.3 0.05 0 5.0.1 host 5.0\n");
  expectReadError(q, {"timestamp", "'5.0.1'"}, 1);
  const auto n = dir.write("count.clf", "FLASER 1e2 1 1 1 2 0.5 3 4 -0.5 10 host 10\n");
  expectReadError(n, {"num_readings", "integer"}, 1);
}

TEST(Carmen, WrongBeamCountIsAnError) {
  TempDir dir;
  expectReadError(dir.write("few.clf", flaser(180, 179)), {"num_readings", "180 ranges", "has 186"}, 1);
  expectReadError(dir.write("many.clf", flaser(180, 181)), {"num_readings", "180 ranges"}, 1);
  const std::string bad_remissions =
      "ROBOTLASER1 0 -1.5 3.0 0.5 20 0.01 0 3 1 2 3 5 1 2 "
      "1 2 0.5 1.1 2.1 0.6 0 0 0 0 0 100.5 host 100.5\n";
  expectReadError(dir.write("rem.clf", bad_remissions), {"num_remissions", "5 remissions"}, 1);
}

TEST(Carmen, TruncatedGzipIsAClearError) {
  TempDir dir;
  const auto aces = test::realLog("aces-corrected.log.gz");
  GLASSMAP_REQUIRE_SHARED_DATA(aces);
  const std::string gz = readFileBytes(aces);
  ASSERT_GT(gz.size(), 1000u);
  const auto p = dir.write("cut.log.gz", gz.substr(0, gz.size() / 2));
  expectReadError(p, {"truncated gzip"});
  // A damaged gzip trailer (CRC) is caught as well.
  std::string bad = gz;
  bad[bad.size() - 6] = static_cast<char>(bad[bad.size() - 6] ^ 0x55);
  expectReadError(dir.write("crc.log.gz", bad), {"gzip"});
}

TEST(Carmen, CompressionDetectedByContentNotExtension) {
  TempDir dir;
  const auto aces = test::realLog("aces-corrected.log.gz");
  GLASSMAP_REQUIRE_SHARED_DATA(aces);
  const std::string gz = readFileBytes(aces);
  const auto misnamed = dir.write("aces.clf", gz);
  EXPECT_EQ(readCarmenLog(misnamed).scans.size(), 440u);
  const auto plain = dir.write("plain.log.gz", flaser(3, 3));
  EXPECT_EQ(readCarmenLog(plain).scans.size(), 1u);
}

TEST(Carmen, EmptyFileIsAnErrorUnlessAllowed) {
  TempDir dir;
  const auto p = dir.write("empty.clf", "");
  expectReadError(p, {"no laser scans", "file is empty"});
  const auto c = dir.write("odom-only.clf", "# only odometry\nODOM 0 0 0 0 0 0 1 h 1\n");
  expectReadError(c, {"no laser scans", "2 lines read"});
  CarmenReadOptions opt;
  opt.require_scans = false;
  const LaserLog log = readCarmenLog(p, opt);
  EXPECT_TRUE(log.scans.empty());
  EXPECT_EQ(log.stats.lines, 0u);
  EXPECT_EQ(readCarmenLog(c, opt).odometry.size(), 1u);
}

TEST(Carmen, MissingFileNamesIt) {
  TempDir dir;
  expectReadError(dir / "nope.clf", {"cannot open"});
}

TEST(Carmen, StreamingMatchesWholeRead) {
  const auto path = test::realLog("aces-corrected.log.gz");
  GLASSMAP_REQUIRE_SHARED_DATA(path);
  std::size_t scans = 0, odom = 0, params = 0, beams = 0;
  CarmenCallbacks cb;
  cb.on_scan = [&](LaserScan&& s) {
    ++scans;
    beams += s.ranges.size();
  };
  cb.on_odometry = [&](const StampedPose&) { ++odom; };
  cb.on_param = [&](const std::string&, const std::string&) { ++params; };
  const LogReadStats stats = forEachCarmenRecord(path, cb);
  EXPECT_EQ(scans, 440u);
  EXPECT_EQ(beams, 440u * 180u);
  EXPECT_EQ(odom, 7814u);
  EXPECT_EQ(params, 4u);
  EXPECT_EQ(stats.scans, 440u);
  EXPECT_EQ(stats.odometry, 7814u);
  EXPECT_EQ(stats.params, 4u);
}

TEST(Carmen, WriterRejectsBadParams) {
  TempDir dir;
  LaserLog log;
  log.params["two words"] = "x";
  EXPECT_THROW(writeCarmenLog(dir / "bad.clf", log), Error);
  EXPECT_FALSE(std::filesystem::exists(dir / "bad.clf"));
}

}  // namespace
}  // namespace glassmap

namespace glassmap {
namespace {

// Every prefix and many random corruptions of a valid log give either a log or a glassmap::Error
// (never another exception, a crash or a hang).
TEST(Carmen, CorruptedInputsGiveErrorsNotCrashes) {
  test::TempDir dir;
  const std::string good =
      "PARAM robot_front_laser_max 30 nohost 0\n"
      "ODOM 1 2 0.1 0.3 0.05 0 5.0 host 5.0\n"
      "FLASER 4 1.0 2.0 nan 3.5 1 2 0.5 3 4 -0.5 10 host 10\n"
      "ROBOTLASER1 0 -1.5 3.0 0.5 20 0.01 0 3 1 2 3 2 7 8 1 2 0.5 1.1 2.1 0.6 0 0 0 0 0 11 host 11\n"
      "RAWLASER2 0 -1.0 2.0 0 30 0.01 0 2 1 2 0 12 host 12\n"
      "TRUEPOS 7 8 0.2 1 2 0.1 13 host 13\n";
  std::size_t errors = 0, logs = 0;
  auto attempt = [&](const std::string& text) {
    const auto p = dir.write("c.clf", text);
    try {
      CarmenReadOptions opt;
      opt.require_scans = false;
      readCarmenLog(p, opt);
      ++logs;
    } catch (const Error& e) {
      ++errors;
      EXPECT_FALSE(std::string(e.what()).empty());
    }
  };
  for (std::size_t n = 0; n <= good.size(); ++n) attempt(good.substr(0, n));
  std::uint32_t state = 12345;
  auto rnd = [&] {
    state = state * 1664525u + 1013904223u;
    return state >> 8;
  };
  const std::string junk = " \t\n-+.eE0x9#Nni/\r";
  for (int trial = 0; trial < 1000; ++trial) {
    std::string text = good;
    for (int k = 0; k < 3; ++k) {
      const std::size_t at = rnd() % text.size();
      switch (rnd() % 3) {
        case 0: text[at] = junk[rnd() % junk.size()]; break;
        case 1: text.erase(at, 1 + rnd() % 8); break;
        default: text.insert(at, 1, junk[rnd() % junk.size()]); break;
      }
      if (text.empty()) text = "#";
    }
    attempt(text);
  }
  EXPECT_GT(errors, 100u);
  EXPECT_GT(logs, 10u);
}

}  // namespace
}  // namespace glassmap

namespace glassmap {
namespace {

TEST(CarmenProgress, ReportsBytesOfTheFileUpToItsSize) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "glassmap_test_progress";
  std::filesystem::create_directories(dir);
  LaserLog log;
  for (int k = 0; k < 20000; ++k) {
    LaserScan s;
    s.timestamp = k * 0.1;
    s.start_angle = -1.5;
    s.angular_step = 0.5;
    s.max_range = 30.0;
    s.ranges = {1.0f, 2.0f, 3.0f, 4.0f, 5.0f, 6.0f, 7.0f};
    s.laser_pose = Pose2(k * 0.01, 0.0, 0.0);
    log.scans.push_back(s);
  }
  for (const char* name : {"p.clf", "p.clf.gz"}) {
    const auto path = dir / name;
    writeCarmenLog(path, log);
    std::vector<std::pair<std::uint64_t, std::uint64_t>> calls;
    CarmenReadOptions o;
    o.progress = [&](std::uint64_t done, std::uint64_t total) { calls.emplace_back(done, total); };
    const LaserLog back = readCarmenLog(path, o);
    EXPECT_EQ(back.scans.size(), log.scans.size());
    ASSERT_GE(calls.size(), 3u) << name;  // every 4096 lines and at the end
    const std::uint64_t size = std::filesystem::file_size(path);
    for (std::size_t i = 0; i < calls.size(); ++i) {
      EXPECT_EQ(calls[i].second, size);
      EXPECT_LE(calls[i].first, size);
      if (i > 0) {
        EXPECT_GE(calls[i].first, calls[i - 1].first);
      }
    }
    EXPECT_EQ(calls.back().first, size);
    EXPECT_GT(calls.front().first, 0u);
    EXPECT_LT(calls.front().first, size);
  }
}

}  // namespace
}  // namespace glassmap
