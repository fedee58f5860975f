#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "glassmap/core/error.hpp"
#include "glassmap/io/ros2_cdr.hpp"

namespace glassmap::ros2 {
namespace {

LaserScanMsg sampleScan(std::mt19937& rng, std::size_t n, const std::string& frame) {
  std::uniform_real_distribution<float> r(0.1f, 30.0f);
  LaserScanMsg m;
  m.header.stamp = {1700000000, 123456789};
  m.header.frame_id = frame;
  m.angle_min = -1.5f;
  m.angle_max = 1.5f;
  m.angle_increment = 3.0f / static_cast<float>(n > 1 ? n - 1 : 1);
  m.time_increment = 1e-4f;
  m.scan_time = 0.1f;
  m.range_min = 0.05f;
  m.range_max = 30.0f;
  for (std::size_t i = 0; i < n; ++i) m.ranges.push_back(r(rng));
  m.ranges.push_back(std::numeric_limits<float>::infinity());
  for (std::size_t i = 0; i < n / 2; ++i) m.intensities.push_back(r(rng));
  return m;
}

OdometryMsg sampleOdom() {
  OdometryMsg m;
  m.header.stamp = {-5, 999999999};
  m.header.frame_id = "odom";
  m.child_frame_id = "base_footprint";
  m.position = {1.5, -2.25, 0.125};
  m.orientation = {0.0, 0.0, std::sin(0.3), std::cos(0.3)};
  for (int i = 0; i < 36; ++i) m.pose_covariance[static_cast<std::size_t>(i)] = 0.01 * i;
  m.linear = {0.5, 0.0, 0.0};
  m.angular = {0.0, 0.0, -0.25};
  for (int i = 0; i < 36; ++i) m.twist_covariance[static_cast<std::size_t>(i)] = -0.5 * i;
  return m;
}

TFMessageMsg sampleTf() {
  TFMessageMsg m;
  for (int k = 0; k < 3; ++k) {
    TransformStampedMsg t;
    t.header.stamp = {100 + k, static_cast<std::uint32_t>(k * 1000)};
    t.header.frame_id = k == 0 ? "map" : "odom";
    t.child_frame_id = std::string(static_cast<std::size_t>(k + 1), 'c');  // lengths 2..4 with NUL: all alignments
    t.translation = {1.0 * k, 2.0, 3.0};
    t.rotation = {0.1, 0.2, 0.3, 0.9};
    m.transforms.push_back(t);
  }
  return m;
}

void expectHeader(const HeaderMsg& a, const HeaderMsg& b) {
  EXPECT_EQ(a.stamp.sec, b.stamp.sec);
  EXPECT_EQ(a.stamp.nanosec, b.stamp.nanosec);
  EXPECT_EQ(a.frame_id, b.frame_id);
}

class CdrEndian : public ::testing::TestWithParam<bool> {};

TEST_P(CdrEndian, LaserScanRoundTrip) {
  std::mt19937 rng(7);
  // frame names of every length mod 8 move the floats after the header to every alignment
  for (const std::string frame : {"", "l", "la", "las", "lase", "laser", "laser_", "laser_f"}) {
    const LaserScanMsg m = sampleScan(rng, 37, frame);
    const auto bytes = encode(m, GetParam());
    ASSERT_EQ(bytes[1], GetParam() ? 0 : 1);
    const LaserScanMsg back = decodeLaserScan(bytes, "t");
    expectHeader(back.header, m.header);
    EXPECT_EQ(back.angle_min, m.angle_min);
    EXPECT_EQ(back.angle_increment, m.angle_increment);
    EXPECT_EQ(back.range_max, m.range_max);
    EXPECT_EQ(back.ranges, m.ranges);
    EXPECT_EQ(back.intensities, m.intensities);
  }
}

TEST_P(CdrEndian, OdometryRoundTripAndDoubleAlignment) {
  const OdometryMsg m = sampleOdom();
  const auto bytes = encode(m, GetParam());
  // relative to the end of the 4-byte header: stamp 0..8, "odom\0" 8..17, pad to 20,
  // "base_footprint\0" 20..39, pad to 40: the position's first float64 starts at byte 4 + 40
  const std::size_t pos_x = 44;
  ASSERT_EQ((pos_x - 4) % 8, 0u);
  double x = 0;
  std::uint64_t u = 0;
  for (int k = 0; k < 8; ++k) u |= std::uint64_t{bytes[pos_x + (GetParam() ? 7 - k : k)]} << (8 * k);
  std::memcpy(&x, &u, 8);
  EXPECT_EQ(x, 1.5);
  EXPECT_EQ(bytes.size(), pos_x + 8 * (3 + 4 + 36 + 6 + 36));
  const OdometryMsg back = decodeOdometry(bytes, "t");
  expectHeader(back.header, m.header);
  EXPECT_EQ(back.child_frame_id, m.child_frame_id);
  EXPECT_EQ(back.position.y, m.position.y);
  EXPECT_EQ(back.orientation.z, m.orientation.z);
  EXPECT_EQ(back.pose_covariance, m.pose_covariance);
  EXPECT_EQ(back.angular.z, m.angular.z);
  EXPECT_EQ(back.twist_covariance, m.twist_covariance);
}

TEST_P(CdrEndian, TfAndMultiEchoRoundTrip) {
  const TFMessageMsg m = sampleTf();
  const TFMessageMsg back = decodeTFMessage(encode(m, GetParam()), "t");
  ASSERT_EQ(back.transforms.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    expectHeader(back.transforms[k].header, m.transforms[k].header);
    EXPECT_EQ(back.transforms[k].child_frame_id, m.transforms[k].child_frame_id);
    EXPECT_EQ(back.transforms[k].translation.x, m.transforms[k].translation.x);
    EXPECT_EQ(back.transforms[k].rotation.w, m.transforms[k].rotation.w);
  }
  MultiEchoLaserScanMsg e;
  e.header.frame_id = "front";
  e.angle_increment = 0.01f;
  e.range_max = 20.0f;
  e.ranges = {{1.0f, 2.0f}, {}, {3.0f}};
  e.intensities = {{5.0f}, {}, {}};
  const MultiEchoLaserScanMsg eb = decodeMultiEchoLaserScan(encode(e, GetParam()), "t");
  EXPECT_EQ(eb.ranges, e.ranges);
  EXPECT_EQ(eb.intensities, e.intensities);
  EXPECT_EQ(eb.header.frame_id, "front");
}

INSTANTIATE_TEST_SUITE_P(LittleAndBig, CdrEndian, ::testing::Values(false, true),
                         [](const auto& info) { return info.param ? "BigEndian" : "LittleEndian"; });

TEST(Cdr, KnownLittleEndianBytes) {
  // A TFMessage with no transforms: header 00 01 00 00, count 0
  EXPECT_EQ(encode(TFMessageMsg{}), (std::vector<std::uint8_t>{0, 1, 0, 0, 0, 0, 0, 0}));
  TFMessageMsg one;
  one.transforms.resize(1);
  one.transforms[0].header.frame_id = "a";
  one.transforms[0].child_frame_id = "b";
  const auto b = encode(one);
  // count 4, stamp 8, "a\0" 4+2 pad 2, "b\0" 4+2 pad 6 -> first double at relative 32
  ASSERT_EQ(b.size(), 4u + 32u + 7u * 8u);
  EXPECT_EQ(b[4 + 12], 2);  // length of "a" with its NUL
  EXPECT_EQ(b[4 + 16], 'a');
  EXPECT_EQ(b[4 + 20], 2);
  EXPECT_EQ(b[4 + 24], 'b');
  EXPECT_EQ(b[4 + 32 + 7 * 8 - 1], 0x3f);  // w = 1.0: 00 .. f0 3f
}

TEST(Cdr, TruncationAtEveryByteThrowsNamingOffset) {
  std::mt19937 rng(3);
  const auto scan = encode(sampleScan(rng, 9, "laser"));
  const auto odom = encode(sampleOdom(), true);
  const auto tf = encode(sampleTf());
  MultiEchoLaserScanMsg e;
  e.ranges = {{1.0f}, {2.0f, 3.0f}};
  const auto multi = encode(e);
  for (std::size_t n = 0; n < scan.size(); ++n) {
    const std::span<const std::uint8_t> part(scan.data(), n);
    try {
      decodeLaserScan(part, "topic /scan message 4");
      // only cutting off the trailing intensities' elements can succeed... never: counts are checked
      ADD_FAILURE() << "decoded a message cut at " << n;
    } catch (const Error& err) {
      EXPECT_NE(std::string(err.what()).find("/scan"), std::string::npos) << err.what();
      EXPECT_NE(std::string(err.what()).find("byte offset"), std::string::npos) << err.what();
    }
  }
  for (std::size_t n = 0; n < odom.size(); ++n)
    EXPECT_THROW(decodeOdometry(std::span<const std::uint8_t>(odom.data(), n), "o"), Error) << n;
  for (std::size_t n = 0; n < tf.size(); ++n)
    EXPECT_THROW(decodeTFMessage(std::span<const std::uint8_t>(tf.data(), n), "tf"), Error) << n;
  for (std::size_t n = 0; n < multi.size(); ++n)
    EXPECT_THROW(decodeMultiEchoLaserScan(std::span<const std::uint8_t>(multi.data(), n), "m"), Error) << n;
}

TEST(Cdr, CorruptedBytesNeverCrash) {
  std::mt19937 rng(11);
  const auto good = encode(sampleTf());
  std::size_t ok = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    auto b = good;
    const int flips = 1 + trial % 4;
    for (int k = 0; k < flips; ++k) b[rng() % b.size()] = static_cast<std::uint8_t>(rng());
    try {
      decodeTFMessage(b, "tf");
      ++ok;
    } catch (const Error&) {
    }
  }
  EXPECT_GT(ok, 0u);  // some flips only change values
}

TEST(Cdr, HugeCountIsRefusedBeforeAllocating) {
  std::vector<std::uint8_t> b{0, 1, 0, 0, 0xff, 0xff, 0xff, 0x7f};
  try {
    decodeTFMessage(b, "topic /tf");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("transforms"), std::string::npos) << e.what();
  }
}

TEST(Cdr, UnsupportedEncapsulation) {
  const std::vector<std::uint8_t> pl{0, 3, 0, 0, 0, 0, 0, 0};  // PL_CDR_LE
  try {
    decodeTFMessage(pl, "topic /tf");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("0x0003"), std::string::npos) << e.what();
  }
}

TEST(Cdr, TimeFromSeconds) {
  const TimeMsg t = TimeMsg::fromSeconds(1700000000.25);
  EXPECT_EQ(t.sec, 1700000000);
  EXPECT_EQ(t.nanosec, 250000000u);
  EXPECT_EQ(TimeMsg::fromSeconds(-0.5).sec, -1);
  EXPECT_EQ(TimeMsg::fromSeconds(-0.5).nanosec, 500000000u);
  for (double s : {0.0, 1.1, 12345.678901234, 1.3e9 + 0.987654321})
    EXPECT_NEAR(TimeMsg::fromSeconds(s).seconds(), s, 1e-9 * (1 + s * 1e-6));
  EXPECT_THROW(TimeMsg::fromSeconds(1e12), Error);
}

TEST(Cdr, SchemaCheck) {
  for (const char* type : {kLaserScanType, kMultiEchoLaserScanType, kOdometryType, kTFMessageType}) {
    const std::string def = messageDefinition(type);
    EXPECT_NO_THROW(checkTopicSchema("/x", type, "cdr", "ros2msg", def)) << def;
    EXPECT_NO_THROW(checkTopicSchema("/x", type, "cdr", "", ""));
  }
  EXPECT_NE(messageDefinition(kOdometryType).find("MSG: geometry_msgs/Quaternion\nfloat64 x 0"), std::string::npos);
  // relative names and comments, constants, /msg/ spellings are accepted
  const std::string laser =
      "# a comment\nuint8 SOME_CONST=3\nstd_msgs/msg/Header header # hdr\nfloat32 angle_min\n"
      "float32 angle_max\nfloat32 angle_increment\nfloat32 time_increment\nfloat32 scan_time\n"
      "float32 range_min\nfloat32 range_max\nfloat32[] ranges\nfloat32[] intensities\n"
      "================================================================================\n"
      "MSG: std_msgs/Header\nbuiltin_interfaces/Time stamp\nstring frame_id\n";
  EXPECT_NO_THROW(checkTopicSchema("/scan", kLaserScanType, "cdr", "ros2msg", laser));
  auto expectError = [](auto fn, const std::string& part) {
    try {
      fn();
      ADD_FAILURE() << "no error, expected " << part;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("/scan"), std::string::npos) << e.what();
    }
  };
  std::string wrong = laser;
  wrong.replace(wrong.find("float32[] ranges"), 16, "float64[] ranges");
  expectError([&] { checkTopicSchema("/scan", kLaserScanType, "cdr", "ros2msg", wrong); }, "float64[] ranges");
  std::string header = laser;
  header.replace(header.find("string frame_id"), 15, "uint32 seq\nstring frame_id");
  expectError([&] { checkTopicSchema("/scan", kLaserScanType, "cdr", "ros2msg", header); }, "std_msgs/Header");
  expectError([&] { checkTopicSchema("/scan", "sensor_msgs/msg/PointCloud2", "cdr", "", ""); }, "PointCloud2");
  expectError([&] { checkTopicSchema("/scan", kLaserScanType, "json", "", ""); }, "json");
  expectError(
      [&] { checkTopicSchema("/scan", kLaserScanType, "cdr", "ros2idl", "struct LaserScan { float ranges; };"); },
      "no field 'header'");
}

}  // namespace
}  // namespace glassmap::ros2
