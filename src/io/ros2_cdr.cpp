// XCDR1 plain CDR reading and writing of the laser-log messages (see ros2_cdr.hpp).
#include "glassmap/io/ros2_cdr.hpp"

#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>

#include "glassmap/core/error.hpp"

namespace glassmap::ros2 {

TimeMsg TimeMsg::fromSeconds(double t) {
  const double sec = std::floor(t);
  if (!std::isfinite(t) || sec < std::numeric_limits<std::int32_t>::min() ||
      sec > std::numeric_limits<std::int32_t>::max())
    throw Error("timestamp " + std::to_string(t) + " s does not fit a ROS 2 Time (int32 seconds)");
  TimeMsg m;
  long long ns = std::llround((t - sec) * 1e9);
  long long s = static_cast<long long>(sec);
  if (ns >= 1'000'000'000) {
    ns -= 1'000'000'000;
    ++s;
  }
  m.sec = static_cast<std::int32_t>(s);
  m.nanosec = static_cast<std::uint32_t>(ns);
  return m;
}

namespace {

constexpr std::size_t kHeaderBytes = 4;  // encapsulation kind (2 bytes) and options (2 bytes)

/// Bounds-checked sequential reader; offsets in errors count from the start of the message.
class CdrReader {
 public:
  CdrReader(std::span<const std::uint8_t> data, const std::string& where) : d_(data), where_(where) {
    if (d_.size() < kHeaderBytes)
      fail("encapsulation header",
           "message of " + std::to_string(d_.size()) + " bytes is shorter than the 4-byte CDR encapsulation header");
    if (d_[0] != 0 || d_[1] > 1) {
      char kind[16];
      std::snprintf(kind, sizeof kind, "0x%02x%02x", d_[0], d_[1]);
      fail("encapsulation header", std::string("unsupported encapsulation ") + kind +
                                       " (plain CDR only: 0x0000 big endian, 0x0001 little endian)");
    }
    little_ = d_[1] == 1;
    pos_ = kHeaderBytes;
  }

  template <class T>
  T prim(const char* field) {
    align(sizeof(T), field);
    need(sizeof(T), field);
    using U = std::conditional_t<sizeof(T) == 8, std::uint64_t,
                                 std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint8_t>>;
    U u = 0;
    for (std::size_t k = 0; k < sizeof(T); ++k) {
      const std::size_t shift = 8 * (little_ ? k : sizeof(T) - 1 - k);
      u |= static_cast<U>(static_cast<U>(d_[pos_ + k]) << shift);
    }
    pos_ += sizeof(T);
    return std::bit_cast<T>(u);
  }

  std::string str(const char* field) {
    const std::uint32_t n = prim<std::uint32_t>(field);
    need(n, field);
    std::size_t len = n;
    if (len > 0 && d_[pos_ + len - 1] == 0) --len;  // the NUL the length counts
    std::string s(reinterpret_cast<const char*>(d_.data() + pos_), len);
    pos_ += n;
    return s;
  }

  /// A sequence count whose elements take at least `min_bytes` each (checked against what is left).
  std::uint32_t count(const char* field, std::size_t min_bytes) {
    const std::uint32_t n = prim<std::uint32_t>(field);
    if (min_bytes > 0 && static_cast<std::uint64_t>(n) * min_bytes > d_.size() - pos_)
      fail(field, "sequence of " + std::to_string(n) + " elements needs at least " +
                      std::to_string(static_cast<std::uint64_t>(n) * min_bytes) + " bytes but " +
                      std::to_string(d_.size() - pos_) + " are left (truncated message?)");
    return n;
  }

  std::vector<float> floats(const char* field) {
    const std::uint32_t n = count(field, 4);
    std::vector<float> v(n);
    for (float& f : v) f = prim<float>(field);
    return v;
  }

  template <std::size_t N>
  void doubles(std::array<double, N>& out, const char* field) {
    for (double& x : out) x = prim<double>(field);
  }

  [[noreturn]] void fail(const char* field, const std::string& what) const {
    throw Error(what + " at byte offset " + std::to_string(pos_), where_, 0, field);
  }

 private:
  void align(std::size_t n, const char* field) {
    const std::size_t rel = pos_ - kHeaderBytes;
    const std::size_t pad = (n - rel % n) % n;
    need(pad, field);
    pos_ += pad;
  }
  void need(std::size_t n, const char* field) const {
    if (d_.size() - pos_ < n)
      fail(field, "truncated message: needs " + std::to_string(n) + " bytes, " + std::to_string(d_.size() - pos_) +
                      " left of " + std::to_string(d_.size()));
  }

  std::span<const std::uint8_t> d_;
  const std::string& where_;
  std::size_t pos_ = 0;
  bool little_ = true;
};

class CdrWriter {
 public:
  explicit CdrWriter(bool big_endian) : little_(!big_endian) {
    b_ = {0, little_ ? std::uint8_t{1} : std::uint8_t{0}, 0, 0};
  }

  template <class T>
  void prim(T v) {
    while ((b_.size() - kHeaderBytes) % sizeof(T) != 0) b_.push_back(0);
    using U = std::conditional_t<sizeof(T) == 8, std::uint64_t,
                                 std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint8_t>>;
    const U u = std::bit_cast<U>(v);
    for (std::size_t k = 0; k < sizeof(T); ++k) {
      const std::size_t shift = 8 * (little_ ? k : sizeof(T) - 1 - k);
      b_.push_back(static_cast<std::uint8_t>(u >> shift));
    }
  }
  void str(const std::string& s) {
    prim(static_cast<std::uint32_t>(s.size() + 1));
    b_.insert(b_.end(), s.begin(), s.end());
    b_.push_back(0);
  }
  void floats(const std::vector<float>& v) {
    prim(static_cast<std::uint32_t>(v.size()));
    for (float f : v) prim(f);
  }
  std::vector<std::uint8_t> take() { return std::move(b_); }

 private:
  bool little_;
  std::vector<std::uint8_t> b_;
};

HeaderMsg readHeader(CdrReader& r) {
  HeaderMsg h;
  h.stamp.sec = r.prim<std::int32_t>("header.stamp.sec");
  h.stamp.nanosec = r.prim<std::uint32_t>("header.stamp.nanosec");
  if (h.stamp.nanosec >= 1'000'000'000u) r.fail("header.stamp.nanosec", "nanoseconds >= 1e9");
  h.frame_id = r.str("header.frame_id");
  return h;
}
void writeHeader(CdrWriter& w, const HeaderMsg& h) {
  w.prim(h.stamp.sec);
  w.prim(h.stamp.nanosec);
  w.str(h.frame_id);
}

template <class Scan>
void readScanFields(CdrReader& r, Scan& m) {
  m.header = readHeader(r);
  m.angle_min = r.prim<float>("angle_min");
  m.angle_max = r.prim<float>("angle_max");
  m.angle_increment = r.prim<float>("angle_increment");
  m.time_increment = r.prim<float>("time_increment");
  m.scan_time = r.prim<float>("scan_time");
  m.range_min = r.prim<float>("range_min");
  m.range_max = r.prim<float>("range_max");
}
template <class Scan>
void writeScanFields(CdrWriter& w, const Scan& m) {
  writeHeader(w, m.header);
  for (float f : {m.angle_min, m.angle_max, m.angle_increment, m.time_increment, m.scan_time, m.range_min, m.range_max})
    w.prim(f);
}

Vector3Msg readVector3(CdrReader& r, const char* field) {
  Vector3Msg v;
  v.x = r.prim<double>(field);
  v.y = r.prim<double>(field);
  v.z = r.prim<double>(field);
  return v;
}
QuaternionMsg readQuaternion(CdrReader& r, const char* field) {
  QuaternionMsg q;
  q.x = r.prim<double>(field);
  q.y = r.prim<double>(field);
  q.z = r.prim<double>(field);
  q.w = r.prim<double>(field);
  return q;
}
void write(CdrWriter& w, const Vector3Msg& v) {
  w.prim(v.x);
  w.prim(v.y);
  w.prim(v.z);
}
void write(CdrWriter& w, const QuaternionMsg& q) {
  w.prim(q.x);
  w.prim(q.y);
  w.prim(q.z);
  w.prim(q.w);
}

std::vector<std::vector<float>> readEchoes(CdrReader& r, const char* field) {
  const std::uint32_t n = r.count(field, 4);  // each LaserEcho holds at least its count
  std::vector<std::vector<float>> v(n);
  for (auto& e : v) e = r.floats(field);
  return v;
}
void writeEchoes(CdrWriter& w, const std::vector<std::vector<float>>& v) {
  w.prim(static_cast<std::uint32_t>(v.size()));
  for (const auto& e : v) w.floats(e);
}

}  // namespace

LaserScanMsg decodeLaserScan(std::span<const std::uint8_t> data, const std::string& where) {
  CdrReader r(data, where);
  LaserScanMsg m;
  readScanFields(r, m);
  m.ranges = r.floats("ranges");
  m.intensities = r.floats("intensities");
  return m;
}

MultiEchoLaserScanMsg decodeMultiEchoLaserScan(std::span<const std::uint8_t> data, const std::string& where) {
  CdrReader r(data, where);
  MultiEchoLaserScanMsg m;
  readScanFields(r, m);
  m.ranges = readEchoes(r, "ranges");
  m.intensities = readEchoes(r, "intensities");
  return m;
}

OdometryMsg decodeOdometry(std::span<const std::uint8_t> data, const std::string& where) {
  CdrReader r(data, where);
  OdometryMsg m;
  m.header = readHeader(r);
  m.child_frame_id = r.str("child_frame_id");
  m.position = readVector3(r, "pose.pose.position");
  m.orientation = readQuaternion(r, "pose.pose.orientation");
  r.doubles(m.pose_covariance, "pose.covariance");
  m.linear = readVector3(r, "twist.twist.linear");
  m.angular = readVector3(r, "twist.twist.angular");
  r.doubles(m.twist_covariance, "twist.covariance");
  return m;
}

TFMessageMsg decodeTFMessage(std::span<const std::uint8_t> data, const std::string& where) {
  CdrReader r(data, where);
  TFMessageMsg m;
  // a TransformStamped takes at least 8 (stamp) + 4 + 4 (two strings) + 56 (seven float64) bytes
  const std::uint32_t n = r.count("transforms", 72);
  m.transforms.resize(n);
  for (TransformStampedMsg& t : m.transforms) {
    t.header = readHeader(r);
    t.child_frame_id = r.str("transforms.child_frame_id");
    t.translation = readVector3(r, "transforms.transform.translation");
    t.rotation = readQuaternion(r, "transforms.transform.rotation");
  }
  return m;
}

std::vector<std::uint8_t> encode(const LaserScanMsg& m, bool big_endian) {
  CdrWriter w(big_endian);
  writeScanFields(w, m);
  w.floats(m.ranges);
  w.floats(m.intensities);
  return w.take();
}

std::vector<std::uint8_t> encode(const MultiEchoLaserScanMsg& m, bool big_endian) {
  CdrWriter w(big_endian);
  writeScanFields(w, m);
  writeEchoes(w, m.ranges);
  writeEchoes(w, m.intensities);
  return w.take();
}

std::vector<std::uint8_t> encode(const OdometryMsg& m, bool big_endian) {
  CdrWriter w(big_endian);
  writeHeader(w, m.header);
  w.str(m.child_frame_id);
  write(w, m.position);
  write(w, m.orientation);
  for (double c : m.pose_covariance) w.prim(c);
  write(w, m.linear);
  write(w, m.angular);
  for (double c : m.twist_covariance) w.prim(c);
  return w.take();
}

std::vector<std::uint8_t> encode(const TFMessageMsg& m, bool big_endian) {
  CdrWriter w(big_endian);
  w.prim(static_cast<std::uint32_t>(m.transforms.size()));
  for (const TransformStampedMsg& t : m.transforms) {
    writeHeader(w, t.header);
    w.str(t.child_frame_id);
    write(w, t.translation);
    write(w, t.rotation);
  }
  return w.take();
}

}  // namespace glassmap::ros2
