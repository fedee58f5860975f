#pragma once
/// The ROS 2 messages of a laser log and their wire format: XCDR1 plain CDR (what rmw writes into
/// bags), a 4-byte encapsulation header (0x00 0x00 big endian, 0x00 0x01 little endian, two
/// option bytes) followed by the fields, each primitive aligned to its size (8 for float64)
/// counted from the end of the header; strings as uint32 length (with the NUL) and the bytes;
/// sequences as uint32 count and the elements; fixed arrays without a count.
///
/// Decoding is bounds-checked: a truncated or inconsistent message throws Error naming `where`
/// (topic and message), the byte offset and the field.

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace glassmap::ros2 {

/// builtin_interfaces/msg/Time.
struct TimeMsg {
  std::int32_t sec = 0;
  std::uint32_t nanosec = 0;
  double seconds() const { return static_cast<double>(sec) + 1e-9 * static_cast<double>(nanosec); }  ///< [s]
  std::int64_t nanoseconds() const { return std::int64_t{sec} * 1'000'000'000 + nanosec; }           ///< [ns]
  static TimeMsg fromSeconds(double t);  ///< nearest nanosecond; throws Error when outside int32 seconds
};

/// std_msgs/msg/Header.
struct HeaderMsg {
  TimeMsg stamp;
  std::string frame_id;
};

/// sensor_msgs/msg/LaserScan (angles [rad], times [s], ranges [m]).
struct LaserScanMsg {
  HeaderMsg header;
  float angle_min = 0, angle_max = 0, angle_increment = 0, time_increment = 0, scan_time = 0;
  float range_min = 0, range_max = 0;
  std::vector<float> ranges, intensities;
};

/// sensor_msgs/msg/MultiEchoLaserScan: per beam a LaserEcho (float32[] echoes).
struct MultiEchoLaserScanMsg {
  HeaderMsg header;
  float angle_min = 0, angle_max = 0, angle_increment = 0, time_increment = 0, scan_time = 0;
  float range_min = 0, range_max = 0;
  std::vector<std::vector<float>> ranges, intensities;
};

struct Vector3Msg {
  double x = 0, y = 0, z = 0;
};
struct QuaternionMsg {
  double x = 0, y = 0, z = 0, w = 1;
};

/// nav_msgs/msg/Odometry (pose in header.frame_id, twist in child_frame_id).
struct OdometryMsg {
  HeaderMsg header;
  std::string child_frame_id;
  Vector3Msg position;
  QuaternionMsg orientation;
  std::array<double, 36> pose_covariance{};
  Vector3Msg linear, angular;  ///< twist [m/s], [rad/s]
  std::array<double, 36> twist_covariance{};
};

/// geometry_msgs/msg/TransformStamped: T_parent_child with parent = header.frame_id.
struct TransformStampedMsg {
  HeaderMsg header;
  std::string child_frame_id;
  Vector3Msg translation;
  QuaternionMsg rotation;
};

/// tf2_msgs/msg/TFMessage.
struct TFMessageMsg {
  std::vector<TransformStampedMsg> transforms;
};

/// Type names as bags declare them.
inline constexpr const char* kLaserScanType = "sensor_msgs/msg/LaserScan";
inline constexpr const char* kMultiEchoLaserScanType = "sensor_msgs/msg/MultiEchoLaserScan";
inline constexpr const char* kOdometryType = "nav_msgs/msg/Odometry";
inline constexpr const char* kTFMessageType = "tf2_msgs/msg/TFMessage";

/// Decoders: `data` is the whole serialized message (encapsulation header included).
LaserScanMsg decodeLaserScan(std::span<const std::uint8_t> data, const std::string& where);
MultiEchoLaserScanMsg decodeMultiEchoLaserScan(std::span<const std::uint8_t> data, const std::string& where);
OdometryMsg decodeOdometry(std::span<const std::uint8_t> data, const std::string& where);
TFMessageMsg decodeTFMessage(std::span<const std::uint8_t> data, const std::string& where);

/// Encoders (little endian unless `big_endian`).
std::vector<std::uint8_t> encode(const LaserScanMsg& m, bool big_endian = false);
std::vector<std::uint8_t> encode(const MultiEchoLaserScanMsg& m, bool big_endian = false);
std::vector<std::uint8_t> encode(const OdometryMsg& m, bool big_endian = false);
std::vector<std::uint8_t> encode(const TFMessageMsg& m, bool big_endian = false);

/// The ros2msg definition of a known type as rosbag2 stores it in a bag (the type's fields, then
/// each nested type after a "====" line and "MSG: pkg/Type"); throws Error for an unknown type.
std::string messageDefinition(const std::string& type);

/// Checks that a topic can be decoded: `type` is one of the four above, `serialization` is "cdr",
/// and, when `schema_text` is given in ros2msg encoding (or "" encoding), its fields (and those of
/// the nested types it defines) have the names and types of the known definition; ros2idl text
/// must name every field. Throws Error naming the topic and what differs.
void checkTopicSchema(const std::string& topic, const std::string& type, const std::string& serialization,
                      const std::string& schema_encoding, const std::string& schema_text);

}  // namespace glassmap::ros2
