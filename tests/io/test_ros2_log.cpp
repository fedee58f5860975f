#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "glassmap/core/angles.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/io/carmen.hpp"
#include "glassmap/io/log.hpp"
#include "glassmap/io/ros2_cdr.hpp"
#include "glassmap/io/ros2_log.hpp"
#include "glassmap/io/ros2_tf.hpp"
#include "io_test_util.hpp"

namespace glassmap {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

/// A robot driving a curve for `n` scans at 10 Hz: SLAM poses, drifting odometry, ranges with
/// no-returns and max readings (seeded).
LaserLog simulatedLog(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  LaserLog log;
  Pose2 truth(2.0, -1.0, 0.3), odom(0.0, 0.0, 0.0);
  for (int k = 0; k < n; ++k) {
    const Pose2 step(0.05 + 0.02 * u(rng), 0.0, 0.04 * (u(rng) - 0.3));
    truth = truth * step;
    odom = odom * Pose2(step.x() * 1.02, 0.001, step.theta + 0.002);  // drift
    LaserScan s;
    s.timestamp = 1700000000.0 + 0.1 * k + 0.013;
    s.start_angle = -deg2rad(90.0);
    s.angular_step = deg2rad(1.0);
    s.max_range = 30.0;
    for (int i = 0; i < 181; ++i) {
      const double p = u(rng);
      s.ranges.push_back(p < 0.05 ? kNoReturn : p < 0.1 ? 30.0f : static_cast<float>(0.5 + 20.0 * u(rng)));
    }
    s.laser_pose = truth;
    s.odom_pose = odom;
    s.has_odom = true;
    log.scans.push_back(s);
    log.odometry.push_back({s.timestamp, odom, 0.5, 0.1});
  }
  return log;
}

void expectSameScans(const LaserLog& carmen, const LaserLog& bag) {
  ASSERT_EQ(carmen.scans.size(), bag.scans.size());
  for (std::size_t i = 0; i < carmen.scans.size(); ++i) {
    SCOPED_TRACE("scan " + std::to_string(i));
    const LaserScan &a = carmen.scans[i], &b = bag.scans[i];
    EXPECT_NEAR(a.timestamp, b.timestamp, 1e-6);
    EXPECT_NEAR(a.start_angle, b.start_angle, 1e-6);  // float32 in the message
    EXPECT_NEAR(a.angular_step, b.angular_step, 1e-8);
    EXPECT_EQ(a.max_range, b.max_range);
    EXPECT_EQ(a.ranges, b.ranges);
    EXPECT_TRUE(approxEqual(a.laser_pose, b.laser_pose, 1e-9, 1e-9)) << b.laser_pose.t.transpose();
    EXPECT_TRUE(approxEqual(a.odom_pose, b.odom_pose, 1e-9, 1e-9));
    EXPECT_TRUE(b.has_odom);
  }
  ASSERT_EQ(carmen.odometry.size(), bag.odometry.size());
  for (std::size_t i = 0; i < carmen.odometry.size(); ++i) {
    EXPECT_NEAR(carmen.odometry[i].timestamp, bag.odometry[i].timestamp, 1e-6);
    EXPECT_TRUE(approxEqual(carmen.odometry[i].pose, bag.odometry[i].pose, 1e-9, 1e-9));
    EXPECT_EQ(carmen.odometry[i].tv, bag.odometry[i].tv);
  }
  EXPECT_EQ(carmen.stats.no_return_ranges, bag.stats.no_return_ranges);
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += x + "\n";
  return s;
}

template <class Fn>
void expectError(Fn fn, const std::vector<std::string>& parts) {
  try {
    fn();
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    for (const auto& p : parts) EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what();
  }
}

struct BagCase {
  const char* name;
  ros2::BagStorage storage;
  ros2::BagCompression compression;
};

class Ros2LogRoundTrip : public ::testing::TestWithParam<BagCase> {};

TEST_P(Ros2LogRoundTrip, BagReadsBackAsTheCarmenLog) {
  TempDir dir;
  const LaserLog sim = simulatedLog(60, 5);
  writeCarmenLog(dir / "sim.clf", sim);
  const LaserLog carmen = readCarmenLog(dir / "sim.clf");
  ros2::BagWriteOptions o;
  o.storage = GetParam().storage;
  o.compression = GetParam().compression;
  o.chunk_size = 4096;  // several chunks
  const Ros2LogWriteResult w = writeRos2Log(carmen, dir / "bag", o);
  EXPECT_EQ(w.scans, 60u);
  EXPECT_EQ(w.odometry, 60u);
  ASSERT_TRUE(isRos2Bag(dir / "bag"));
  EXPECT_FALSE(isRos2Bag(dir / "sim.clf"));

  LogReadNotes notes;
  const LaserLog bag = readLog(dir / "bag", {}, &notes);
  expectSameScans(carmen, bag);
  EXPECT_NE(joined(notes.notes).find("map -> odom (/tf) -> base_link (/tf) -> laser (tf)"), std::string::npos)
      << joined(notes.notes);
  EXPECT_TRUE(notes.warnings.empty()) << joined(notes.warnings);

  // odometry poses only: the laser sits at base_link (identity static transform)
  LogReadOptions odo;
  odo.ros2.pose_source = BagPoseSource::Odometry;
  const LaserLog by_odom = readLog(dir / "bag", odo, &notes);
  ASSERT_EQ(by_odom.scans.size(), carmen.scans.size());
  for (std::size_t i = 0; i < carmen.scans.size(); ++i)
    EXPECT_TRUE(approxEqual(by_odom.scans[i].laser_pose, carmen.scans[i].odom_pose, 1e-9, 1e-9));
  EXPECT_NE(joined(notes.notes).find("ignored"), std::string::npos);

  // the summary
  const Ros2BagSummary s = summarizeRos2Bag(dir / "bag");
  EXPECT_EQ(s.topics.size(), 4u);
  EXPECT_EQ(s.messages, 60u + 60u + 60u + 1u);
  EXPECT_NEAR(s.duration(), 5.9, 1e-6);
  ASSERT_EQ(s.transforms.size(), 3u);
  EXPECT_EQ(s.scan_frames, std::vector<std::string>{"laser"});
  bool static_laser = false;
  for (const auto& t : s.transforms) static_laser = static_laser || (t.child == "laser" && t.is_static);
  EXPECT_TRUE(static_laser);
}

INSTANTIATE_TEST_SUITE_P(Storages, Ros2LogRoundTrip,
                         ::testing::Values(BagCase{"McapZstd", ros2::BagStorage::Mcap, ros2::BagCompression::Zstd},
                                           BagCase{"McapLz4", ros2::BagStorage::Mcap, ros2::BagCompression::Lz4},
                                           BagCase{"Sqlite3", ros2::BagStorage::Sqlite3, ros2::BagCompression::None}),
                         [](const auto& info) { return std::string(info.param.name); });

/// Writes a bag by hand: /scan with `scans` (stamps t), /odom with poses at `odom_times`.
struct HandBag {
  ros2::BagWriter writer;
  explicit HandBag(const fs::path& p, ros2::BagStorage storage = ros2::BagStorage::Mcap)
      : writer(p, [&] {
          ros2::BagWriteOptions o;
          o.storage = storage;
          o.compression = ros2::BagCompression::None;
          return o;
        }()) {}
  int topic(const std::string& name, const std::string& type) {
    return writer.addTopic(name, type, ros2::messageDefinition(type));
  }
  void scan(int id, double t, const std::string& frame, bool big_endian = false) {
    ros2::LaserScanMsg m;
    m.header.stamp = ros2::TimeMsg::fromSeconds(t);
    m.header.frame_id = frame;
    m.angle_min = -1.0f;
    m.angle_increment = 0.5f;
    m.angle_max = 1.0f;
    m.range_min = 0.1f;
    m.range_max = 10.0f;
    m.ranges = {1.0f, std::numeric_limits<float>::quiet_NaN(), 0.05f, 12.0f, -std::numeric_limits<float>::infinity()};
    writer.write(id, m.header.stamp.nanoseconds(), ros2::encode(m, big_endian));
  }
  void odom(int id, double t, const Pose2& p) {
    ros2::OdometryMsg m;
    m.header.stamp = ros2::TimeMsg::fromSeconds(t);
    m.header.frame_id = "odom";
    m.child_frame_id = "base_footprint";
    m.position = {p.x(), p.y(), 0.0};
    m.orientation = ros2::yawQuaternion(p.theta);
    writer.write(id, m.header.stamp.nanoseconds(), ros2::encode(m));
  }
};

TEST(Ros2Log, OdometryOnlyBagWarnsAndInterpolates) {
  TempDir dir;
  {
    HandBag b(dir / "bag", ros2::BagStorage::Sqlite3);
    const int scan = b.topic("/front_scan", ros2::kLaserScanType);
    const int odom = b.topic("/wheel_odom", ros2::kOdometryType);
    for (int k = 0; k <= 10; ++k) b.odom(odom, 100.0 + 0.1 * k, Pose2(0.1 * k, 0.0, 0.05 * k));
    for (int k = 0; k < 5; ++k) b.scan(scan, 100.05 + 0.2 * k, "front_laser", k % 2 == 1);
    b.scan(scan, 101.5, "front_laser");  // beyond the odometry: skipped
    b.writer.close();
  }
  LogReadNotes notes;
  const LaserLog log = readLog(dir / "bag", {}, &notes);
  ASSERT_EQ(log.scans.size(), 5u);
  EXPECT_NEAR(log.scans[1].laser_pose.x(), 0.25, 1e-9);  // between 0.2 and 0.3
  EXPECT_NEAR(log.scans[1].laser_pose.theta, 0.125, 1e-9);
  EXPECT_NEAR(log.scans[1].odom_pose.x(), 0.25, 1e-9);
  const std::string w = joined(notes.warnings);
  EXPECT_NE(w.find("no map -> odom transform"), std::string::npos) << w;
  EXPECT_NE(w.find("no base_footprint -> front_laser transform"), std::string::npos) << w;
  EXPECT_NE(w.find("1 of 6 scans skipped"), std::string::npos) << w;
  EXPECT_NE(joined(notes.notes).find("/wheel_odom odometry messages"), std::string::npos) << joined(notes.notes);
  // REP 117 readings: NaN, below range_min and -inf are no returns; beyond range_max a max reading
  const LaserScan& s = log.scans[0];
  EXPECT_EQ(s.ranges[0], 1.0f);
  EXPECT_EQ(s.ranges[1], kNoReturn);
  EXPECT_EQ(s.ranges[2], kNoReturn);
  EXPECT_EQ(s.ranges[3], 12.0f);
  EXPECT_FALSE(s.isReturn(3));
  EXPECT_EQ(s.ranges[4], kNoReturn);
  EXPECT_EQ(log.stats.no_return_ranges, 6u * 3u);  // counted over every message decoded
  EXPECT_NEAR(s.angular_step, 0.5, 1e-12);
  EXPECT_EQ(log.odometry.size(), 11u);

  // map poses demanded: an error naming the frames
  LogReadOptions map_only;
  map_only.ros2.pose_source = BagPoseSource::Map;
  expectError([&] { readLog(dir / "bag", map_only); }, {"no map -> odom transform", "bag"});
}

TEST(Ros2Log, TopicChoiceErrorsNameTheTopics) {
  TempDir dir;
  {
    HandBag b(dir / "no_scan");
    const int odom = b.topic("/odom", ros2::kOdometryType);
    b.odom(odom, 1.0, Pose2());
    b.writer.close();
  }
  expectError([&] { readLog(dir / "no_scan"); }, {"no sensor_msgs/msg/LaserScan", "/odom (nav_msgs/msg/Odometry)"});
  {
    HandBag b(dir / "two");
    const int a = b.topic("/scan_a", ros2::kLaserScanType);
    const int c = b.topic("/scan_b", ros2::kLaserScanType);
    const int odom = b.topic("/odom", ros2::kOdometryType);
    for (int k = 0; k < 3; ++k) {
      b.odom(odom, 1.0 + k, Pose2(k, 0, 0));
      b.scan(a, 1.0 + k, "base_footprint");
      b.scan(c, 1.5 + k, "base_footprint");
    }
    b.writer.close();
  }
  expectError([&] { readLog(dir / "two"); }, {"/scan_a, /scan_b", "--scan-topic"});
  LogReadOptions pick;
  pick.ros2.scan_topic = "/scan_b";
  EXPECT_EQ(readLog(dir / "two", pick).scans.size(), 2u);  // the last is beyond the odometry
  pick.ros2.scan_topic = "/odom";
  expectError([&] { readLog(dir / "two", pick); }, {"/odom (--scan-topic) has type nav_msgs/msg/Odometry"});
  pick.ros2.scan_topic = "/nope";
  expectError([&] { readLog(dir / "two", pick); }, {"/nope", "/scan_a (sensor_msgs/msg/LaserScan)"});
}

TEST(Ros2Log, WrongSchemaOrTypeNamesTheTopic) {
  TempDir dir;
  {
    ros2::BagWriter w(dir / "bad");
    std::string def = ros2::messageDefinition(ros2::kLaserScanType);
    def.replace(def.find("float32 range_max"), 17, "float64 range_max");
    const int id = w.addTopic("/scan", ros2::kLaserScanType, def);
    ros2::LaserScanMsg m;
    w.write(id, 1, ros2::encode(m));
    w.close();
  }
  expectError([&] { readLog(dir / "bad"); }, {"/scan", "float64 range_max"});
  {
    ros2::BagWriter w(dir / "pc");
    const int id = w.addTopic("/scan", "sensor_msgs/msg/PointCloud2", "");
    w.write(id, 1, std::vector<std::uint8_t>{0, 1, 0, 0});
    w.close();
  }
  LogReadOptions pick;
  pick.ros2.scan_topic = "/scan";
  expectError([&] { readLog(dir / "pc", pick); }, {"/scan", "PointCloud2"});
}

TEST(Ros2Log, TruncatedBagOrMessageIsAnError) {
  TempDir dir;
  const LaserLog sim = simulatedLog(40, 9);
  ros2::BagWriteOptions o;
  o.compression = ros2::BagCompression::None;
  writeRos2Log(sim, dir / "bag", o);
  fs::path mcap;
  for (const auto& e : fs::directory_iterator(dir / "bag"))
    if (e.path().extension() == ".mcap") mcap = e.path();
  ASSERT_FALSE(mcap.empty());
  fs::resize_file(mcap, fs::file_size(mcap) / 2);
  EXPECT_THROW(readLog(mcap), Error);

  // a message cut short inside a valid bag: the error names the topic and the offset
  {
    ros2::BagWriter w(dir / "cut");
    const int id = w.addTopic("/scan", ros2::kLaserScanType, ros2::messageDefinition(ros2::kLaserScanType));
    ros2::LaserScanMsg m;
    m.header.frame_id = "laser";
    m.range_max = 5.0f;
    m.ranges.assign(10, 1.0f);
    auto bytes = ros2::encode(m);
    bytes.resize(bytes.size() - 6);
    w.write(id, 1, bytes);
    w.close();
  }
  expectError([&] { readLog(dir / "cut"); }, {"topic /scan, message 0", "byte offset", "ranges"});
  // info still summarises it, naming the message that did not decode
  const Ros2BagSummary sum = summarizeRos2Bag(dir / "cut");
  EXPECT_EQ(sum.messages, 1u);
  std::string all;
  for (const auto& n : sum.notes) all += n + "\n";
  EXPECT_NE(all.find("1 messages could not be decoded; the first: "), std::string::npos) << all;
  EXPECT_NE(all.find("topic /scan, message 0"), std::string::npos) << all;
}

TEST(Ros2Log, ExtrapolationMultiEchoAndMemoryLimit) {
  TempDir dir;
  {
    HandBag b(dir / "bag");
    const int scan = b.topic("/multi", ros2::kMultiEchoLaserScanType);
    const int tf = b.topic("/tf", ros2::kTFMessageType);
    const int tfs = b.topic("/tf_static", ros2::kTFMessageType);
    ros2::TFMessageMsg st;
    ros2::TransformStampedMsg laser;
    laser.header.frame_id = "base_link";
    laser.child_frame_id = "laser";
    laser.translation = {0.3, 0.0, 0.2};
    laser.rotation = ros2::yawQuaternion(kPi);
    st.transforms.push_back(laser);
    b.writer.write(tfs, 0, ros2::encode(st));
    for (int k = 0; k < 10; ++k) {
      ros2::TFMessageMsg m;
      ros2::TransformStampedMsg t;
      t.header.stamp = ros2::TimeMsg::fromSeconds(10.0 + 0.1 * k);
      t.header.frame_id = "odom";
      t.child_frame_id = "base_link";
      t.translation = {0.1 * k, 0.0, 0.0};
      m.transforms.push_back(t);
      b.writer.write(tf, t.header.stamp.nanoseconds(), ros2::encode(m));
    }
    for (double t : {9.5, 10.35, 10.95, 11.5}) {
      ros2::MultiEchoLaserScanMsg m;
      m.header.stamp = ros2::TimeMsg::fromSeconds(t);
      m.header.frame_id = "laser";
      m.angle_increment = 0.1f;
      m.range_max = 8.0f;
      m.ranges = {{2.0f, 3.0f}, {}, {4.0f}};
      b.writer.write(scan, m.header.stamp.nanoseconds(), ros2::encode(m));
    }
    b.writer.close();
  }
  LogReadNotes notes;
  const LaserLog log = readLog(dir / "bag", {}, &notes);
  ASSERT_EQ(log.scans.size(), 2u);  // 9.5 and 11.5 lie beyond the tolerance
  EXPECT_EQ(log.scans[0].ranges, (std::vector<float>{2.0f, kNoReturn, 4.0f}));
  EXPECT_TRUE(approxEqual(log.scans[0].laser_pose, Pose2(0.35 + 0.3, 0.0, kPi), 1e-9, 1e-9));
  EXPECT_TRUE(approxEqual(log.scans[1].laser_pose, Pose2(0.9 + 0.3, 0.0, kPi), 1e-9, 1e-9));  // held 0.05 s
  EXPECT_NE(joined(notes.warnings).find("2 of 4 scans skipped: no odom -> base_link"), std::string::npos)
      << joined(notes.warnings);
  EXPECT_NE(joined(notes.notes).find("first echo"), std::string::npos);

  LogReadOptions small;
  small.carmen.max_memory_bytes = 100;
  expectError([&] { readLog(dir / "bag", small); }, {"memory limit"});

  // Kept on disk instead (a folder to spool to): the same scans, poses and warnings.
  fs::create_directories(dir / "spool");
  small.carmen.spool_directory = dir / "spool";
  small.carmen.spool_above_bytes = 1;
  LogReadNotes spool_notes;
  const LaserLog disk = readLog(dir / "bag", small, &spool_notes);
  ASSERT_TRUE(disk.spooled.has_value());
  EXPECT_TRUE(disk.scans.empty());
  EXPECT_EQ(disk.scanCount(), 2u);
  EXPECT_EQ(disk.stats.scans, 2u);
  EXPECT_EQ(spool_notes.warnings, notes.warnings);
  std::vector<LaserScan> back;
  forEachScanBlock(disk,
                   [&](std::span<const LaserScan> b, std::size_t) { back.insert(back.end(), b.begin(), b.end()); });
  ASSERT_EQ(back.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(back[i].ranges, log.scans[i].ranges);
    EXPECT_TRUE(approxEqual(back[i].laser_pose, log.scans[i].laser_pose, 0.0, 0.0));
    EXPECT_EQ(back[i].timestamp, log.scans[i].timestamp);
  }
  EXPECT_TRUE(fs::is_empty(dir / "spool"));
}

TEST(Ros2Log, NegativeStampsKeptLogTimesShifted) {
  TempDir dir;
  LaserLog sim = simulatedLog(20, 2);
  for (LaserScan& s : sim.scans) s.timestamp -= 1700000001.0;  // relative times from -0.987 s
  for (StampedPose& p : sim.odometry) p.timestamp -= 1700000001.0;
  const Ros2LogWriteResult w = writeRos2Log(sim, dir / "bag");
  ASSERT_EQ(w.notes.size(), 1u);
  EXPECT_NE(w.notes[0].find("stamps before 0"), std::string::npos) << w.notes[0];
  const LaserLog back = readLog(dir / "bag");
  ASSERT_EQ(back.scans.size(), sim.scans.size());
  for (std::size_t i = 0; i < sim.scans.size(); ++i) {
    EXPECT_NEAR(back.scans[i].timestamp, sim.scans[i].timestamp, 1e-9);
    EXPECT_TRUE(approxEqual(back.scans[i].laser_pose, sim.scans[i].laser_pose, 1e-9, 1e-9));
  }
  EXPECT_LT(back.scans.front().timestamp, 0.0);
  EXPECT_NEAR(summarizeRos2Bag(dir / "bag").t_first, 0.0, 1e-9);
}

TEST(Ros2Log, CarmenLogsStillReadThroughReadLog) {
  TempDir dir;
  const LaserLog sim = simulatedLog(5, 1);
  writeCarmenLog(dir / "a.clf", sim);
  LogReadNotes notes;
  notes.notes.push_back("stale");
  EXPECT_EQ(readLog(dir / "a.clf", {}, &notes).scans.size(), 5u);
  EXPECT_TRUE(notes.notes.empty());
  EXPECT_THROW(writeRos2Log(LaserLog{}, dir / "empty"), Error);
  EXPECT_FALSE(fs::exists(dir / "empty"));
}

}  // namespace
}  // namespace glassmap
