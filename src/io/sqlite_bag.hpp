#pragma once
// rosbag2 SQLite storage (.db3) through libsqlite3. Private to the io module; use openBag().
//
// Tables: topics(id, name, type, serialization_format, offered_qos_profiles[, type_description_hash])
// and messages(id, topic_id, timestamp, data); the `schema`, `metadata` and `message_definitions`
// tables of newer rosbag2 versions are read when present.

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "glassmap/io/ros2_bag.hpp"

struct sqlite3;
struct sqlite3_stmt;

namespace glassmap::ros2 {

class SqliteFileReader final : public BagReader {
 public:
  explicit SqliteFileReader(const std::filesystem::path& path);
  ~SqliteFileReader() override;
  const std::vector<BagTopic>& topics() const override { return topics_; }
  void forEach(const std::set<std::string>& topic_names, const std::function<bool(const BagMessage&)>& fn,
               const std::function<void(std::uint64_t, std::uint64_t)>& progress = {}) const override;
  BagStorage storage() const override { return BagStorage::Sqlite3; }
  std::vector<std::filesystem::path> files() const override { return {path_}; }
  std::vector<std::string> notes() const override { return notes_; }

 private:
  std::filesystem::path path_;
  std::string name_;
  sqlite3* db_ = nullptr;
  std::vector<BagTopic> topics_;
  std::vector<std::int64_t> topic_ids_;  ///< topics_[i] has id topic_ids_[i]
  std::uint64_t total_ = 0;
  std::vector<std::string> notes_;
};

/// Writes a .db3 as rosbag2 does (schema version 4 layout with message_definitions).
class SqliteWriter {
 public:
  explicit SqliteWriter(const std::filesystem::path& path);
  ~SqliteWriter();
  SqliteWriter(const SqliteWriter&) = delete;
  SqliteWriter& operator=(const SqliteWriter&) = delete;
  /// Adds a topic; returns its id (1, 2, ...).
  std::int64_t addTopic(const std::string& name, const std::string& type, const std::string& schema_text);
  void write(std::int64_t topic_id, std::int64_t timestamp_ns, std::span<const std::uint8_t> data);
  /// Commits and closes; throws Error on failure.
  void finish();

 private:
  void exec(const char* sql);
  std::filesystem::path path_;
  std::string name_;
  sqlite3* db_ = nullptr;
  sqlite3_stmt* insert_ = nullptr;
  std::int64_t topics_ = 0;
};

}  // namespace glassmap::ros2
