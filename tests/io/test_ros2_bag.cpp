// ROS 2 bags, MCAP storage: round trips through BagWriter/openBag for every compression with and
// without a summary, log-time order, topic filter, early stop, and broken files (truncated, bad
// magic, CRC mismatches, unknown compression, hostile lengths) read from hand-built bytes.

#include <gtest/gtest.h>

#include <algorithm>
#include <tuple>

#include "glassmap/core/error.hpp"
#include "glassmap/io/ros2_bag.hpp"
#include "io_test_util.hpp"
#include "test_ros2_bag_util.hpp"

namespace glassmap {
namespace {

namespace fs = std::filesystem;
using ros2::BagCompression;
using ros2::BagStorage;
using ros2::BagWriteOptions;
using test::McapBytes;
using test::TempDir;
using test::TestMessage;
using test::errorOf;
using test::sortedByTime;

class McapRoundTrip : public ::testing::TestWithParam<std::tuple<BagCompression, bool>> {};

TEST_P(McapRoundTrip, MessagesAndTopicsComeBack) {
  const auto [compression, summary] = GetParam();
  TempDir dir;
  const auto messages = test::testMessages(600, 7);
  BagWriteOptions opt;
  opt.compression = compression;
  opt.write_summary = summary;
  opt.chunk_size = 4096;  // many chunks
  test::writeTestBag(dir / "bag", messages, opt);
  ASSERT_TRUE(fs::exists(dir / "bag" / "metadata.yaml"));
  ASSERT_TRUE(fs::exists(dir / "bag" / "bag_0.mcap"));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 1);  // no staging left

  for (const fs::path& p : {dir / "bag", dir / "bag" / "bag_0.mcap"}) {
    ASSERT_TRUE(ros2::isBag(p)) << p;
    const auto bag = ros2::openBag(p);
    EXPECT_EQ(bag->storage(), BagStorage::Mcap);
    ASSERT_EQ(bag->files().size(), 1u);
    const auto topics = test::testTopics();
    ASSERT_EQ(bag->topics().size(), topics.size());
    for (std::size_t i = 0; i < topics.size(); ++i) {
      const auto& t = bag->topics()[i];
      EXPECT_EQ(t.name, topics[i].name);
      EXPECT_EQ(t.type, topics[i].type);
      EXPECT_EQ(t.schema_text, topics[i].schema);
      EXPECT_EQ(t.schema_encoding, "ros2msg");
      EXPECT_EQ(t.serialization_format, "cdr");
      EXPECT_EQ(t.message_count,
                static_cast<std::uint64_t>(std::count_if(messages.begin(), messages.end(),
                                                         [&](const TestMessage& m) { return m.topic == t.name; })));
    }
    const auto notes = bag->notes();
    const std::string mode = summary ? "chunk indexes in log-time order" : "read linearly in file order";
    EXPECT_TRUE(std::any_of(notes.begin(), notes.end(),
                            [&](const std::string& n) { return n.find(mode) != std::string::npos; }));
    // Indexed: log-time order across chunks; linear: file (= write) order.
    EXPECT_EQ(test::readAll(*bag), summary ? sortedByTime(messages) : messages);
  }
}

INSTANTIATE_TEST_SUITE_P(Ros2Bag, McapRoundTrip,
                         ::testing::Combine(::testing::Values(BagCompression::None, BagCompression::Zstd,
                                                              BagCompression::Lz4),
                                            ::testing::Bool()));

TEST(Ros2Bag, DescendingTimesComeBackSortedAndFilterAndStop) {
  TempDir dir;
  std::vector<TestMessage> messages;
  for (int i = 0; i < 300; ++i)
    messages.push_back({i % 3 == 0 ? "/odom" : "/scan", 1'000'000'000LL - 1000 * i, 1'000'000'000LL - 1000 * i,
                        std::vector<std::uint8_t>(static_cast<std::size_t>(i % 50), static_cast<std::uint8_t>(i))});
  BagWriteOptions opt;
  opt.chunk_size = 1000;
  test::writeTestBag(dir / "bag", messages, opt);
  const auto bag = ros2::openBag(dir / "bag");
  const auto all = test::readAll(*bag);
  EXPECT_EQ(all, sortedByTime(messages));

  // Topic filter: only /odom, still sorted.
  std::vector<TestMessage> odom;
  for (const auto& m : sortedByTime(messages))
    if (m.topic == "/odom") odom.push_back(m);
  EXPECT_EQ(test::readAll(*bag, {"/odom"}), odom);
  EXPECT_TRUE(test::readAll(*bag, {"/nothing"}).empty());

  // Early stop after 10 messages; progress reaches the end only when not stopped.
  int seen = 0;
  std::uint64_t last_done = 0, total = 0;
  bag->forEach(
      {}, [&](const ros2::BagMessage&) { return ++seen < 10; },
      [&](std::uint64_t d, std::uint64_t t) {
        EXPECT_GE(d, last_done);
        last_done = d;
        total = t;
      });
  EXPECT_EQ(seen, 10);
  EXPECT_GT(total, 0u);
}

TEST(Ros2Bag, EmptyMcapBag) {
  for (bool summary : {false, true}) {
    TempDir dir;
    BagWriteOptions opt;
    opt.write_summary = summary;
    ros2::BagWriter w(dir / "empty", opt);
    (void)w.addTopic("/scan", "sensor_msgs/msg/LaserScan", "");
    w.close();
    const auto bag = ros2::openBag(dir / "empty");
    ASSERT_EQ(bag->topics().size(), 1u);
    EXPECT_EQ(bag->topics()[0].message_count, 0u);
    EXPECT_TRUE(test::readAll(*bag).empty());
  }
  TempDir dir;
  {
    ros2::BagWriter w(dir / "none");
    w.close();
  }
  EXPECT_TRUE(ros2::openBag(dir / "none")->topics().empty());
}

TEST(Ros2Bag, HandBuiltMcapWithoutSummaryIsReadLinearly) {
  TempDir dir;
  McapBytes f;
  f.magic().header().schema(1, "std_msgs/msg/String", "string data\n").channel(3, 1, "/chatter");
  f.record(0x05, McapBytes::message(3, 50, 40, {1, 2}));
  f.record(0x05, McapBytes::message(3, 20, 10, {3}));
  f.record(0x0C, McapBytes().str("meta").u32(0));  // a Metadata record: skipped
  f.record(0x80, McapBytes().u64(1));              // an application extension: skipped
  f.record(0x05, McapBytes::message(3, 30, 30, {}));
  f.dataEnd().footer().magic();
  test::writeBytes(dir / "hand.mcap", f.b);
  const auto bag = ros2::openBag(dir / "hand.mcap");
  ASSERT_EQ(bag->topics().size(), 1u);
  EXPECT_EQ(bag->topics()[0].type, "std_msgs/msg/String");
  EXPECT_EQ(bag->topics()[0].message_count, 3u);
  const std::vector<TestMessage> want = {
      {"/chatter", 50, 40, {1, 2}}, {"/chatter", 20, 10, {3}}, {"/chatter", 30, 30, {}}};
  EXPECT_EQ(test::readAll(*bag), want);

  // The same with a wrong data section CRC is refused at the Data End record.
  McapBytes g;
  g.magic().header().schema(1, "a", "").channel(1, 1, "/a").record(0x05, McapBytes::message(1, 1, 1, {9}));
  const std::size_t data_end_at = g.b.size();
  g.dataEnd(12345).footer().magic();
  test::writeBytes(dir / "crc.mcap", g.b);
  const std::string err = errorOf([&] { (void)ros2::openBag(dir / "crc.mcap"); });
  EXPECT_NE(err.find("crc.mcap"), std::string::npos) << err;
  EXPECT_NE(err.find("byte " + std::to_string(data_end_at)), std::string::npos) << err;
  EXPECT_NE(err.find("CRC"), std::string::npos) << err;
}

TEST(Ros2Bag, TruncatedMcapDeliversCompleteMessagesThenFails) {
  TempDir dir;
  const auto messages = test::testMessages(120, 3);
  for (bool summary : {false, true}) {
    BagWriteOptions opt;
    opt.write_summary = summary;
    opt.chunk_size = 2000;
    opt.compression = BagCompression::None;  // a bigger file: more cuts inside the data
    const fs::path bagdir = dir / (summary ? "s" : "n");
    test::writeTestBag(bagdir, messages, opt);
    const auto bytes = test::readBytes(bagdir / (bagdir.filename().string() + "_0.mcap"));
    std::vector<std::size_t> cuts;
    for (std::size_t c = 0; c < bytes.size(); c += 151) cuts.push_back(c);
    for (std::size_t c = bytes.size() > 64 ? bytes.size() - 64 : 0; c < bytes.size(); ++c) cuts.push_back(c);
    int partial = 0;
    for (std::size_t cut : cuts) {
      const fs::path p = dir / "cut.mcap";
      test::writeBytes(p, std::vector<std::uint8_t>(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(cut)));
      std::vector<TestMessage> got;
      const std::string err = errorOf([&] {
        const auto bag = ros2::openBag(p);
        bag->forEach({}, [&](const ros2::BagMessage& m) {
          got.push_back({m.topic->name, m.log_time_ns, m.publish_time_ns, {m.data.begin(), m.data.end()}});
          return true;
        });
      });
      ASSERT_FALSE(err.empty()) << "cut at " << cut << " read without error";
      EXPECT_NE(err.find("cut.mcap"), std::string::npos) << err;
      // What came before the error is a prefix of the file order.
      ASSERT_LE(got.size(), messages.size());
      EXPECT_TRUE(std::equal(got.begin(), got.end(), messages.begin())) << "cut at " << cut;
      if (!got.empty()) {
        ++partial;
        EXPECT_NE(err.find("truncated"), std::string::npos) << err;
      }
    }
    EXPECT_GT(partial, 5);
  }
}

TEST(Ros2Bag, BadMagicAndCorruptChunks) {
  TempDir dir;
  test::writeBytes(dir / "x.mcap", {0x89, 'M', 'C', 'A', 'P', '1', '\r', '\n', 0, 0, 0});
  EXPECT_FALSE(ros2::isBag(dir / "x.mcap"));
  EXPECT_NE(errorOf([&] { (void)ros2::openBag(dir / "x.mcap"); }).find("not a ROS 2 bag"), std::string::npos);
  EXPECT_FALSE(ros2::isBag(dir / "missing.mcap"));
  EXPECT_NE(errorOf([&] { (void)ros2::openBag(dir / "missing.mcap"); }).find("missing.mcap"), std::string::npos);

  // An SQLite file is a bag, unless its header's application id says GeoPackage (a floorplan).
  std::vector<std::uint8_t> sqlite(100, 0);
  const char* magic = "SQLite format 3";
  std::copy(magic, magic + 16, sqlite.begin());  // with its terminating zero
  test::writeBytes(dir / "plan.db3", sqlite);
  EXPECT_TRUE(ros2::isBag(dir / "plan.db3"));
  std::copy_n("GPKG", 4, sqlite.begin() + 68);
  test::writeBytes(dir / "plan.gpkg", sqlite);
  EXPECT_FALSE(ros2::isBag(dir / "plan.gpkg"));

  // A flipped payload byte in an uncompressed chunk: the chunk CRC catches it, naming the chunk.
  for (bool summary : {false, true}) {
    BagWriteOptions opt;
    opt.compression = BagCompression::None;
    opt.write_summary = summary;
    const fs::path bagdir = dir / (summary ? "crc_s" : "crc_n");
    std::vector<TestMessage> msgs = {{"/scan", 5, 5, {0xAB, 0xCD, 0xEF, 0x12, 0x34}}};
    test::writeTestBag(bagdir, msgs, opt);
    const fs::path file = bagdir / (bagdir.filename().string() + "_0.mcap");
    auto bytes = test::readBytes(file);
    const std::vector<std::uint8_t> pattern = {0xAB, 0xCD, 0xEF, 0x12, 0x34};
    const auto it = std::search(bytes.begin(), bytes.end(), pattern.begin(), pattern.end());
    ASSERT_NE(it, bytes.end());
    *(it + 2) ^= 0xFF;
    test::writeBytes(file, bytes);
    const std::string err = errorOf([&] { (void)test::readAll(*ros2::openBag(file)); });
    EXPECT_NE(err.find("CRC mismatch"), std::string::npos) << err;
    EXPECT_NE(err.find("Chunk"), std::string::npos) << err;
  }
}

McapBytes chunkRecord(const std::string& compression, std::uint64_t uncompressed_size,
                      const std::vector<std::uint8_t>& records) {
  McapBytes c;
  c.u64(1).u64(1).u64(uncompressed_size).u32(0).str(compression).u64(records.size()).raw(records);
  return c;
}

TEST(Ros2Bag, UnknownCompressionAndHostileLengths) {
  TempDir dir;
  McapBytes inner;
  inner.schema(1, "a", "").channel(1, 1, "/a").record(0x05, McapBytes::message(1, 1, 1, {1}));
  McapBytes f;
  f.magic().header();
  const std::size_t chunk_at = f.b.size();
  f.record(0x06, chunkRecord("brotli", inner.b.size(), inner.b)).dataEnd().footer().magic();
  test::writeBytes(dir / "brotli.mcap", f.b);
  std::string err = errorOf([&] { (void)ros2::openBag(dir / "brotli.mcap"); });
  EXPECT_NE(err.find("unknown compression 'brotli'"), std::string::npos) << err;
  EXPECT_NE(err.find("byte " + std::to_string(chunk_at)), std::string::npos) << err;

  // A zstd chunk claiming 1 TB uncompressed: refused before any allocation.
  McapBytes g;
  g.magic()
      .header()
      .record(0x06, chunkRecord("zstd", 1ull << 40, {0x28, 0xB5, 0x2F, 0xFD, 0, 0}))
      .dataEnd()
      .footer()
      .magic();
  test::writeBytes(dir / "huge.mcap", g.b);
  err = errorOf([&] { (void)ros2::openBag(dir / "huge.mcap"); });
  EXPECT_NE(err.find("implausible uncompressed size"), std::string::npos) << err;

  // A record length of 2^62: the file is truncated there, no allocation attempted.
  McapBytes h;
  h.magic().header();
  const std::size_t bad_at = h.b.size();
  h.u8(0x05).u64(1ull << 62).u64(0);
  test::writeBytes(dir / "long.mcap", h.b);
  err = errorOf([&] { (void)test::readAll(*ros2::openBag(dir / "long.mcap")); });
  EXPECT_NE(err.find("byte " + std::to_string(bad_at)), std::string::npos) << err;
  EXPECT_NE(err.find("truncated"), std::string::npos) << err;

  // A message on a channel no record declares.
  McapBytes k;
  k.magic().header().record(0x05, McapBytes::message(9, 1, 1, {})).dataEnd().footer().magic();
  test::writeBytes(dir / "nochan.mcap", k.b);
  err = errorOf([&] { (void)ros2::openBag(dir / "nochan.mcap"); });
  EXPECT_NE(err.find("channel 9"), std::string::npos) << err;
}

/// A hand-built indexed MCAP: one uncompressed chunk, then a summary whose chunk indexes are
/// given as (offset, length) pairs relative to the chunk (`{0, 0}` = the chunk itself).
std::vector<std::uint8_t> indexedMcap(const std::vector<std::pair<std::int64_t, std::int64_t>>& indexes) {
  McapBytes inner;
  inner.schema(1, "a", "").channel(1, 1, "/a").record(0x05, McapBytes::message(1, 7, 6, {4, 2}));
  McapBytes f;
  f.magic().header();
  const std::uint64_t chunk_at = f.b.size();
  f.record(0x06, chunkRecord("", inner.b.size(), inner.b));
  const std::uint64_t chunk_length = f.b.size() - chunk_at;
  f.dataEnd();
  const std::uint64_t summary_at = f.b.size();
  f.schema(1, "a", "").channel(1, 1, "/a");
  for (const auto& [off, len] : indexes) {
    McapBytes c;
    c.u64(7).u64(7).u64(chunk_at + static_cast<std::uint64_t>(off)).u64(chunk_length + static_cast<std::uint64_t>(len));
    c.u32(0).u64(0).str("").u64(inner.b.size()).u64(inner.b.size());
    f.record(0x08, c);
  }
  f.record(0x02, McapBytes().u64(summary_at).u64(0).u32(0)).magic();
  return f.b;
}

TEST(Ros2Bag, HandBuiltIndexedMcapAndBadChunkIndexes) {
  TempDir dir;
  // The same chunk indexed twice is read once.
  test::writeBytes(dir / "twice.mcap", indexedMcap({{0, 0}, {0, 0}}));
  const auto bag = ros2::openBag(dir / "twice.mcap");
  const std::vector<TestMessage> want = {{"/a", 7, 6, {4, 2}}};
  EXPECT_EQ(test::readAll(*bag), want);
  ASSERT_EQ(bag->topics().size(), 1u);
  EXPECT_EQ(bag->topics()[0].message_count, 1u);
  // Overlapping chunks, a chunk past the end of the file, an index not pointing at a chunk.
  test::writeBytes(dir / "overlap.mcap", indexedMcap({{0, 0}, {1, -1}}));
  EXPECT_NE(errorOf([&] { (void)ros2::openBag(dir / "overlap.mcap"); }).find("overlapping"), std::string::npos);
  test::writeBytes(dir / "past.mcap", indexedMcap({{0, 1ll << 40}}));
  EXPECT_NE(errorOf([&] { (void)ros2::openBag(dir / "past.mcap"); }).find("outside the file"), std::string::npos);
  test::writeBytes(dir / "shifted.mcap", indexedMcap({{1, 0}}));
  EXPECT_NE(errorOf([&] { (void)test::readAll(*ros2::openBag(dir / "shifted.mcap")); }).find("no Chunk record"),
            std::string::npos);
}

}  // namespace
}  // namespace glassmap
