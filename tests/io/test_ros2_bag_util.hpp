#pragma once
// Helpers of the ROS 2 bag tests: seeded message sets, reading a bag back into memory, and a
// little-endian encoder to build MCAP files by hand (independent of the writer under test).

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "glassmap/core/error.hpp"
#include "glassmap/io/ros2_bag.hpp"

namespace glassmap::test {

struct TestMessage {
  std::string topic;
  std::int64_t log_time = 0;
  std::int64_t publish_time = 0;
  std::vector<std::uint8_t> data;
  bool operator==(const TestMessage&) const = default;
};

struct TestTopic {
  std::string name, type, schema;
};

inline std::vector<TestTopic> testTopics() {
  return {{"/scan", "sensor_msgs/msg/LaserScan", "std_msgs/Header header\nfloat32 angle_min\nfloat32[] ranges\n"},
          {"/odom", "nav_msgs/msg/Odometry", "std_msgs/Header header\nstring child_frame_id\n"},
          {"/tf", "tf2_msgs/msg/TFMessage", "geometry_msgs/TransformStamped[] transforms\n"}};
}

/// `n` messages on the test topics with seeded random payloads (0..300 bytes, compressible) and
/// distinct log times shuffled out of order.
inline std::vector<TestMessage> testMessages(int n, unsigned seed) {
  std::mt19937 rng(seed);
  const auto topics = testTopics();
  std::vector<std::int64_t> times;
  for (int i = 0; i < n; ++i) times.push_back(1'700'000'000'000'000'000LL + 1000LL * i + (i % 7));
  std::shuffle(times.begin(), times.end(), rng);
  std::vector<TestMessage> out;
  for (int i = 0; i < n; ++i) {
    TestMessage m;
    m.topic = topics[rng() % topics.size()].name;
    m.log_time = m.publish_time = times[static_cast<std::size_t>(i)];
    m.data.resize(rng() % 301);
    for (auto& b : m.data) b = static_cast<std::uint8_t>(rng() % 8);
    out.push_back(std::move(m));
  }
  return out;
}

/// Writes a bag with the test topics and `messages`.
inline void writeTestBag(const std::filesystem::path& dir, const std::vector<TestMessage>& messages,
                         const ros2::BagWriteOptions& options) {
  ros2::BagWriter w(dir, options);
  std::vector<std::string> names;
  for (const auto& t : testTopics()) {
    (void)w.addTopic(t.name, t.type, t.schema);
    names.push_back(t.name);
  }
  for (const auto& m : messages)
    w.write(static_cast<int>(std::find(names.begin(), names.end(), m.topic) - names.begin()), m.log_time, m.data);
  w.close();
}

/// Every message of a bag (optionally of some topics), in the order the reader gives them.
inline std::vector<TestMessage> readAll(const ros2::BagReader& bag, const std::set<std::string>& topics = {}) {
  std::vector<TestMessage> out;
  bag.forEach(topics, [&](const ros2::BagMessage& m) {
    out.push_back({m.topic->name, m.log_time_ns, m.publish_time_ns, {m.data.begin(), m.data.end()}});
    return true;
  });
  return out;
}

inline std::vector<std::uint8_t> readBytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline void writeBytes(const std::filesystem::path& p, const std::vector<std::uint8_t>& bytes) {
  std::ofstream(p, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

/// Builds MCAP bytes by hand (https://mcap.dev/spec).
class McapBytes {
 public:
  McapBytes& u8(std::uint8_t v) { return le(v, 1); }
  McapBytes& u16(std::uint16_t v) { return le(v, 2); }
  McapBytes& u32(std::uint32_t v) { return le(v, 4); }
  McapBytes& u64(std::uint64_t v) { return le(v, 8); }
  McapBytes& str(const std::string& s) {
    u32(static_cast<std::uint32_t>(s.size()));
    b.insert(b.end(), s.begin(), s.end());
    return *this;
  }
  McapBytes& raw(const std::vector<std::uint8_t>& v) {
    b.insert(b.end(), v.begin(), v.end());
    return *this;
  }
  McapBytes& magic() { return raw({0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'}); }
  McapBytes& record(std::uint8_t op, const McapBytes& content) {
    u8(op);
    u64(content.b.size());
    return raw(content.b);
  }
  McapBytes& header() { return record(0x01, McapBytes().str("ros2").str("hand")); }
  McapBytes& schema(std::uint16_t id, const std::string& name, const std::string& text) {
    return record(0x03, McapBytes().u16(id).str(name).str("ros2msg").str(text));
  }
  McapBytes& channel(std::uint16_t id, std::uint16_t schema, const std::string& topic) {
    return record(0x04, McapBytes().u16(id).u16(schema).str(topic).str("cdr").u32(0));
  }
  static McapBytes message(std::uint16_t channel, std::uint64_t log, std::uint64_t pub,
                           const std::vector<std::uint8_t>& data) {
    McapBytes m;
    m.u16(channel).u32(0).u64(log).u64(pub).raw(data);
    return m;
  }
  McapBytes& dataEnd(std::uint32_t crc = 0) { return record(0x0F, McapBytes().u32(crc)); }
  McapBytes& footer() { return record(0x02, McapBytes().u64(0).u64(0).u32(0)); }
  std::vector<std::uint8_t> b;

 private:
  McapBytes& le(std::uint64_t v, int n) {
    for (int i = 0; i < n; ++i) b.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
    return *this;
  }
};

/// The messages in log-time order (stable: equal times keep their order).
inline std::vector<TestMessage> sortedByTime(std::vector<TestMessage> v) {
  std::stable_sort(v.begin(), v.end(),
                   [](const TestMessage& a, const TestMessage& b) { return a.log_time < b.log_time; });
  return v;
}

/// Error thrown by `f`, or an empty message when it does not throw.
template <typename F>
std::string errorOf(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace glassmap::test
