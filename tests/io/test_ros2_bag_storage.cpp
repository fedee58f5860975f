// ROS 2 bags beyond one MCAP file: SQLite .db3 (written by BagWriter and built with SQL as
// rosbag2 does), rosbag2 directories (several files, FILE and MESSAGE zstd compression, missing
// files), telling bags apart by content, the writer's refusals, and an MCAP file written by the
// reference TypeScript library (tests/data/io/ros2_mcap_js.mcap: overlapping chunks, an
// attachment, a metadata record, statistics and summary offsets).

#include <gtest/gtest.h>
#include <sqlite3.h>
#include <zstd.h>

#include <algorithm>

#include "glassmap/core/error.hpp"
#include "glassmap/io/ros2_bag.hpp"
#include "io_test_util.hpp"
#include "test_ros2_bag_util.hpp"

namespace glassmap {
namespace {

namespace fs = std::filesystem;
using ros2::BagStorage;
using ros2::BagWriteOptions;
using test::TempDir;
using test::TestMessage;
using test::errorOf;
using test::sortedByTime;

/// Runs SQL statements on a database, failing the test on an error.
void sql(sqlite3* db, const std::string& statements) {
  char* err = nullptr;
  ASSERT_EQ(sqlite3_exec(db, statements.c_str(), nullptr, nullptr, &err), SQLITE_OK) << (err ? err : "");
}

/// A .db3 as rosbag2 (Foxy/Humble) creates it: no schema table; messages inserted out of time
/// order; `compress` zstd-compresses each message (MESSAGE mode).
void handBuiltDb3(const fs::path& path, const std::vector<TestMessage>& messages, bool compress = false) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  sql(db,
      "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL, "
      "serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);"
      "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, timestamp INTEGER NOT NULL, "
      "data BLOB NOT NULL);"
      "CREATE INDEX timestamp_idx ON messages (timestamp ASC);"
      "INSERT INTO topics VALUES (7, '/scan', 'sensor_msgs/msg/LaserScan', 'cdr', '- history: 3');"
      "INSERT INTO topics VALUES (9, '/odom', 'nav_msgs/msg/Odometry', 'cdr', '');");
  sqlite3_stmt* st = nullptr;
  ASSERT_EQ(
      sqlite3_prepare_v2(db, "INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ?, ?)", -1, &st, nullptr),
      SQLITE_OK);
  sql(db, "BEGIN TRANSACTION;");
  for (const auto& m : messages) {
    std::vector<std::uint8_t> data = m.data;
    if (compress) {
      data.resize(ZSTD_compressBound(m.data.size()));
      data.resize(ZSTD_compress(data.data(), data.size(), m.data.data(), m.data.size(), 1));
    }
    sqlite3_reset(st);
    sqlite3_bind_int(st, 1, m.topic == "/scan" ? 7 : 9);
    sqlite3_bind_int64(st, 2, m.log_time);
    sqlite3_bind_blob(st, 3, data.empty() ? "" : static_cast<const void*>(data.data()), static_cast<int>(data.size()),
                      SQLITE_TRANSIENT);
    ASSERT_EQ(sqlite3_step(st), SQLITE_DONE);
  }
  sqlite3_finalize(st);
  sql(db, "COMMIT;");
  sqlite3_close(db);
}

std::vector<TestMessage> scanOdomMessages(int n, unsigned seed) {
  auto v = test::testMessages(n, seed);
  for (auto& m : v)
    if (m.topic == "/tf") m.topic = "/odom";
  return v;
}

TEST(Ros2BagStorage, Db3RoundTripThroughTheWriter) {
  TempDir dir;
  const auto messages = test::testMessages(400, 11);
  BagWriteOptions opt;
  opt.storage = BagStorage::Sqlite3;
  test::writeTestBag(dir / "bag", messages, opt);
  ASSERT_TRUE(fs::exists(dir / "bag" / "bag_0.db3"));
  for (const fs::path& p : {dir / "bag", dir / "bag" / "bag_0.db3"}) {
    ASSERT_TRUE(ros2::isBag(p));
    const auto bag = ros2::openBag(p);
    EXPECT_EQ(bag->storage(), BagStorage::Sqlite3);
    const auto topics = test::testTopics();
    ASSERT_EQ(bag->topics().size(), topics.size());
    for (std::size_t i = 0; i < topics.size(); ++i) {
      EXPECT_EQ(bag->topics()[i].name, topics[i].name);
      EXPECT_EQ(bag->topics()[i].type, topics[i].type);
      EXPECT_EQ(bag->topics()[i].schema_text, topics[i].schema);
    }
    EXPECT_EQ(test::readAll(*bag), sortedByTime(messages));
    int seen = 0;
    bag->forEach({"/odom"}, [&](const ros2::BagMessage& m) {
      EXPECT_EQ(m.topic->name, "/odom");
      return ++seen < 5;
    });
    EXPECT_EQ(seen, 5);
  }
  // An empty db3 bag.
  BagWriteOptions o;
  o.storage = BagStorage::Sqlite3;
  {
    ros2::BagWriter w(dir / "empty", o);
    w.close();
  }
  const auto empty = ros2::openBag(dir / "empty");
  EXPECT_TRUE(empty->topics().empty());
  EXPECT_TRUE(test::readAll(*empty).empty());
}

TEST(Ros2BagStorage, HandBuiltDb3WithoutSchemaTable) {
  TempDir dir;
  const auto messages = scanOdomMessages(200, 5);
  handBuiltDb3(dir / "rosbag2.db3", messages);
  const auto bag = ros2::openBag(dir / "rosbag2.db3");
  ASSERT_EQ(bag->topics().size(), 2u);
  EXPECT_EQ(bag->topics()[0].name, "/scan");
  EXPECT_EQ(bag->topics()[1].type, "nav_msgs/msg/Odometry");
  EXPECT_EQ(bag->topics()[0].message_count + bag->topics()[1].message_count, 200u);
  EXPECT_EQ(test::readAll(*bag), sortedByTime(messages));

  // A db3 file without the rosbag2 tables, and a truncated one.
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open((dir / "other.db3").c_str(), &db), SQLITE_OK);
  sql(db, "CREATE TABLE t(x);");
  sqlite3_close(db);
  EXPECT_NE(errorOf([&] { (void)ros2::openBag(dir / "other.db3"); }).find("no table 'topics'"), std::string::npos);
  auto bytes = test::readBytes(dir / "rosbag2.db3");
  bytes.resize(bytes.size() / 2);
  test::writeBytes(dir / "cut.db3", bytes);
  EXPECT_NE(errorOf([&] { (void)test::readAll(*ros2::openBag(dir / "cut.db3")); }).find("cut.db3"), std::string::npos);
}

TEST(Ros2BagStorage, Db3WithWriteAheadLogOfARunningRecording) {
  TempDir dir;
  const fs::path path = dir / "live.db3";
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  sql(db,
      "PRAGMA journal_mode=WAL; PRAGMA wal_autocheckpoint=0;"
      "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL, "
      "serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);"
      "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, timestamp INTEGER NOT NULL, "
      "data BLOB NOT NULL);"
      "INSERT INTO topics VALUES (1, '/scan', 'sensor_msgs/msg/LaserScan', 'cdr', '');"
      "INSERT INTO messages (topic_id, timestamp, data) VALUES (1, 20, x'0102'), (1, 10, x'03');");
  ASSERT_TRUE(fs::exists(path.string() + "-wal"));  // the messages are still only in the log
  const std::vector<TestMessage> want = {{"/scan", 10, 10, {3}}, {"/scan", 20, 20, {1, 2}}};
  EXPECT_EQ(test::readAll(*ros2::openBag(path)), want);
  sqlite3_close(db);
}

/// metadata.yaml of a directory bag listing `files`.
std::string metadataYaml(const std::string& storage, const std::vector<std::string>& files,
                         const std::string& compression = "", const std::string& mode = "") {
  std::string y =
      "rosbag2_bagfile_information:\n  version: 5\n  storage_identifier: " + storage + "\n  relative_file_paths:\n";
  for (const auto& f : files) y += "    - " + f + "\n";
  y += "  compression_format: \"" + compression + "\"\n  compression_mode: \"" + mode + "\"\n";
  return y;
}

TEST(Ros2BagStorage, DirectoryWithTwoFilesAndFileCompression) {
  TempDir dir;
  const auto first = test::testMessages(150, 1), second = test::testMessages(100, 2);
  test::writeTestBag(dir / "a", first, {});
  test::writeTestBag(dir / "b", second, {});
  fs::create_directory(dir / "two");
  fs::copy_file(dir / "a" / "a_0.mcap", dir / "two" / "two_0.mcap");
  fs::copy_file(dir / "b" / "b_0.mcap", dir / "two" / "two_1.mcap");
  dir.write("two/metadata.yaml", metadataYaml("mcap", {"two_0.mcap", "two_1.mcap"}));
  ASSERT_TRUE(ros2::isBag(dir / "two"));
  const auto bag = ros2::openBag(dir / "two");
  ASSERT_EQ(bag->files().size(), 2u);
  ASSERT_EQ(bag->topics().size(), 3u);
  std::uint64_t total = 0;
  for (const auto& t : bag->topics()) total += t.message_count;
  EXPECT_EQ(total, 250u);
  auto want = sortedByTime(first);
  for (const auto& m : sortedByTime(second)) want.push_back(m);  // files in order
  EXPECT_EQ(test::readAll(*bag), want);
  std::uint64_t last = 0, all = 0;
  bag->forEach(
      {"/scan"}, [](const ros2::BagMessage&) { return true; },
      [&](std::uint64_t d, std::uint64_t t) {
        EXPECT_GE(d, last);
        last = d;
        all = t;
      });
  EXPECT_EQ(last, all);

  // FILE mode: the same files zstd-compressed as rosbag2 names them.
  fs::create_directory(dir / "z");
  for (const char* f : {"two_0.mcap", "two_1.mcap"}) {
    const auto raw = test::readBytes(dir / "two" / f);
    std::vector<std::uint8_t> z(ZSTD_compressBound(raw.size()));
    z.resize(ZSTD_compress(z.data(), z.size(), raw.data(), raw.size(), 3));
    test::writeBytes(dir / "z" / (std::string(f) + ".zstd"), z);
  }
  dir.write("z/metadata.yaml", metadataYaml("mcap", {"two_0.mcap.zstd", "two_1.mcap.zstd"}, "zstd", "FILE"));
  EXPECT_EQ(test::readAll(*ros2::openBag(dir / "z")), want);

  // A listed file that is not there: named with metadata.yaml and its line.
  fs::remove(dir / "two" / "two_1.mcap");
  const std::string err = errorOf([&] { (void)ros2::openBag(dir / "two"); });
  EXPECT_NE(err.find("metadata.yaml:6"), std::string::npos) << err;
  EXPECT_NE(err.find("two_1.mcap"), std::string::npos) << err;
  // Unknown compression format, broken YAML.
  dir.write("two/metadata.yaml", metadataYaml("mcap", {"two_0.mcap"}, "bz2", "FILE"));
  EXPECT_NE(errorOf([&] { (void)ros2::openBag(dir / "two"); }).find("'bz2'"), std::string::npos);
  dir.write("two/metadata.yaml", "rosbag2_bagfile_information: [\n");
  EXPECT_NE(errorOf([&] { (void)ros2::openBag(dir / "two"); }).find("metadata.yaml"), std::string::npos);
}

TEST(Ros2BagStorage, MessageCompressionMode) {
  TempDir dir;
  const auto messages = scanOdomMessages(120, 9);
  fs::create_directory(dir / "m");
  handBuiltDb3(dir / "m" / "m_0.db3", messages, /*compress=*/true);
  dir.write("m/metadata.yaml", metadataYaml("sqlite3", {"m_0.db3"}, "zstd", "MESSAGE"));
  EXPECT_EQ(test::readAll(*ros2::openBag(dir / "m")), sortedByTime(messages));
}

TEST(Ros2BagStorage, TellingBagsApartAndWriterRefusals) {
  TempDir dir;
  dir.write("notes.txt", "hello");
  EXPECT_FALSE(ros2::isBag(dir / "notes.txt"));
  EXPECT_FALSE(ros2::isBag(dir.path()));  // a folder without metadata.yaml
  EXPECT_NE(errorOf([&] { (void)ros2::openBag(dir / "notes.txt"); }).find("not a ROS 2 bag"), std::string::npos);
  EXPECT_NE(errorOf([&] { (void)ros2::openBag(dir.path()); }).find("metadata.yaml"), std::string::npos);

  // The writer refuses a non-empty folder; an unclosed writer leaves nothing behind.
  fs::create_directory(dir / "full");
  dir.write("full/x", "x");
  EXPECT_THROW(ros2::BagWriter(dir / "full"), Error);
  {
    ros2::BagWriter w(dir / "abandoned");
    const int t = w.addTopic("/a", "std_msgs/msg/String", "string data\n");
    w.write(t, 5, std::vector<std::uint8_t>{1, 2, 3});
    EXPECT_THROW(w.write(t + 1, 5, std::vector<std::uint8_t>{}), Error);
    EXPECT_THROW((void)w.addTopic("/a", "std_msgs/msg/String", ""), Error);
  }
  EXPECT_FALSE(fs::exists(dir / "abandoned"));
  std::vector<std::string> left;
  for (const auto& e : fs::directory_iterator(dir.path())) left.push_back(e.path().filename().string());
  std::sort(left.begin(), left.end());
  EXPECT_EQ(left, (std::vector<std::string>{"full", "notes.txt"}));
  // An existing empty folder is fine.
  fs::create_directory(dir / "empty");
  {
    ros2::BagWriter w(dir / "empty");
    w.close();
  }
  EXPECT_TRUE(ros2::isBag(dir / "empty"));
}

TEST(Ros2BagStorage, ReadsTheReferenceLibrarysMcap) {
  const fs::path file = fs::path(GLASSMAP_SOURCE_DIR) / "tests/data/io/ros2_mcap_js.mcap";
  const auto bag = ros2::openBag(file);
  ASSERT_EQ(bag->topics().size(), 2u);
  EXPECT_EQ(bag->topics()[0].name, "/a");
  EXPECT_EQ(bag->topics()[0].message_count, 80u);
  EXPECT_EQ(bag->topics()[1].message_count, 40u);
  EXPECT_EQ(bag->topics()[0].type, "std_msgs/msg/String");
  const auto all = test::readAll(*bag);
  ASSERT_EQ(all.size(), 120u);
  for (std::size_t i = 0; i < all.size(); ++i) {
    EXPECT_EQ(all[i].log_time, static_cast<std::int64_t>(10 * i + 5));  // overlapping chunks merged in time order
    EXPECT_EQ(all[i].publish_time, all[i].log_time + 1);
    EXPECT_EQ(all[i].data.size(), 4u);
  }
}

}  // namespace
}  // namespace glassmap
