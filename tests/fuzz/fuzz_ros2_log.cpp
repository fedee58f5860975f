// libFuzzer target: the CDR decoders of the ROS 2 log messages (LaserScan, MultiEchoLaserScan,
// Odometry, TFMessage) and the schema check. The first byte picks what the rest is fed to; a
// message that decodes must encode and decode again to the same message.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <span>
#include <string>

#include "glassmap/core/error.hpp"
#include "glassmap/io/ros2_cdr.hpp"

namespace {

using namespace glassmap::ros2;

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

template <class V>
bool sameFloats(const V& a, const V& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (!sameBits(a[i], b[i])) return false;
  return true;
}

bool sameHeader(const HeaderMsg& a, const HeaderMsg& b) {
  return a.stamp.sec == b.stamp.sec && a.stamp.nanosec == b.stamp.nanosec && a.frame_id == b.frame_id;
}

void check(bool ok) {
  if (!ok) std::abort();  // a decoded message that does not survive its own encoding
}

void roundTrip(const LaserScanMsg& m, bool big) {
  const LaserScanMsg b = decodeLaserScan(encode(m, big), "again");
  check(sameHeader(m.header, b.header) && sameFloats(m.ranges, b.ranges) && sameFloats(m.intensities, b.intensities) &&
        sameBits(m.angle_increment, b.angle_increment) && sameBits(m.range_max, b.range_max));
}

void roundTrip(const MultiEchoLaserScanMsg& m, bool big) {
  const MultiEchoLaserScanMsg b = decodeMultiEchoLaserScan(encode(m, big), "again");
  check(sameHeader(m.header, b.header) && m.ranges.size() == b.ranges.size() &&
        m.intensities.size() == b.intensities.size());
  for (std::size_t i = 0; i < m.ranges.size(); ++i) check(sameFloats(m.ranges[i], b.ranges[i]));
}

void roundTrip(const OdometryMsg& m, bool big) {
  const OdometryMsg b = decodeOdometry(encode(m, big), "again");
  check(sameHeader(m.header, b.header) && m.child_frame_id == b.child_frame_id &&
        sameBits(m.position.x, b.position.x) && sameBits(m.orientation.w, b.orientation.w) &&
        sameFloats(m.pose_covariance, b.pose_covariance) && sameFloats(m.twist_covariance, b.twist_covariance) &&
        sameBits(m.angular.z, b.angular.z));
}

void roundTrip(const TFMessageMsg& m, bool big) {
  const TFMessageMsg b = decodeTFMessage(encode(m, big), "again");
  check(m.transforms.size() == b.transforms.size());
  for (std::size_t i = 0; i < m.transforms.size(); ++i) {
    const auto &x = m.transforms[i], &y = b.transforms[i];
    check(sameHeader(x.header, y.header) && x.child_frame_id == y.child_frame_id &&
          sameBits(x.translation.y, y.translation.y) && sameBits(x.rotation.z, y.rotation.z));
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::span<const std::uint8_t> msg(data + 1, size - 1);
  const bool big = size > 2 && data[2] == 0;  // the encapsulation's byte order, for the re-encoding
  try {
    switch (data[0] % 5) {
      case 0: roundTrip(decodeLaserScan(msg, "fuzz /scan"), big); break;
      case 1: roundTrip(decodeMultiEchoLaserScan(msg, "fuzz /scan"), big); break;
      case 2: roundTrip(decodeOdometry(msg, "fuzz /odom"), big); break;
      case 3: roundTrip(decodeTFMessage(msg, "fuzz /tf"), big); break;
      default: {
        const std::string text(reinterpret_cast<const char*>(msg.data()), msg.size());
        checkTopicSchema("/scan", kLaserScanType, "cdr", "ros2msg", text);
        checkTopicSchema("/odom", kOdometryType, "cdr", "ros2idl", text);
      }
    }
  } catch (const glassmap::Error&) {
  }
  return 0;
}
