#include "sqlite_bag.hpp"

#include <sqlite3.h>

#include <map>
#include <memory>

#include "glassmap/core/error.hpp"

namespace glassmap::ros2 {
namespace {

struct StmtDeleter {
  void operator()(sqlite3_stmt* s) const { sqlite3_finalize(s); }
};
using Stmt = std::unique_ptr<sqlite3_stmt, StmtDeleter>;

[[noreturn]] void fail(sqlite3* db, const std::string& name, const std::string& what) {
  throw Error(what + ": " + (db ? sqlite3_errmsg(db) : "out of memory"), name);
}

Stmt prepare(sqlite3* db, const std::string& name, const std::string& sql) {
  sqlite3_stmt* s = nullptr;
  if (sqlite3_prepare_v2(db, sql.c_str(), -1, &s, nullptr) != SQLITE_OK) fail(db, name, "SQL '" + sql + "'");
  return Stmt(s);
}

bool hasTable(sqlite3* db, const std::string& name, const std::string& table) {
  Stmt s = prepare(db, name, "SELECT 1 FROM sqlite_master WHERE type='table' AND name=?");
  sqlite3_bind_text(s.get(), 1, table.c_str(), -1, SQLITE_TRANSIENT);
  const int rc = sqlite3_step(s.get());
  if (rc != SQLITE_ROW && rc != SQLITE_DONE) fail(db, name, "reading the table list");
  return rc == SQLITE_ROW;
}

/// "file:" URI of a path for sqlite3_open_v2, with the characters URIs reserve escaped.
std::string fileUri(const std::filesystem::path& path) {
  std::string uri = "file:";
  for (const char c : std::filesystem::absolute(path).string()) {
    if (c == '%' || c == '?' || c == '#') {
      static const char hex[] = "0123456789ABCDEF";
      uri += '%';
      uri += hex[static_cast<unsigned char>(c) >> 4];
      uri += hex[static_cast<unsigned char>(c) & 15];
    } else {
      uri += c;
    }
  }
  return uri;
}

std::string text(sqlite3_stmt* s, int col) {
  const auto* p = sqlite3_column_text(s, col);
  return p ? std::string(reinterpret_cast<const char*>(p), static_cast<std::size_t>(sqlite3_column_bytes(s, col))) : "";
}

}  // namespace

SqliteFileReader::SqliteFileReader(const std::filesystem::path& path) : path_(path), name_(path.string()) {
  // Read-only and immutable (no lock files next to the bag), unless a write-ahead log of an
  // interrupted recording (rosbag2's resilient preset) holds messages still to be read.
  std::error_code ec;
  const bool wal = std::filesystem::exists(path.string() + "-wal", ec);
  const std::string uri = fileUri(path) + (wal ? "?mode=ro" : "?immutable=1");
  if (sqlite3_open_v2(uri.c_str(), &db_, SQLITE_OPEN_READONLY | SQLITE_OPEN_URI, nullptr) != SQLITE_OK) {
    const std::string why = db_ ? sqlite3_errmsg(db_) : "out of memory";
    sqlite3_close(db_);
    db_ = nullptr;
    throw Error("cannot open the SQLite bag: " + why, name_);
  }
  try {
    for (const char* t : {"topics", "messages"})
      if (!hasTable(db_, name_, t)) throw Error(std::string("not a rosbag2 SQLite bag: no table '") + t + "'", name_);
    if (hasTable(db_, name_, "schema")) {
      Stmt s = prepare(db_, name_, "SELECT schema_version, ros_distro FROM schema");
      if (sqlite3_step(s.get()) == SQLITE_ROW)
        notes_.push_back("rosbag2 SQLite schema version " + std::to_string(sqlite3_column_int64(s.get(), 0)) +
                         ", ROS distro '" + text(s.get(), 1) + "'");
    }
    std::map<std::string, std::pair<std::string, std::string>> definitions;  // type → (encoding, text)
    if (hasTable(db_, name_, "message_definitions")) {
      Stmt s = prepare(db_, name_, "SELECT topic_type, encoding, encoded_message_definition FROM message_definitions");
      while (sqlite3_step(s.get()) == SQLITE_ROW) definitions[text(s.get(), 0)] = {text(s.get(), 1), text(s.get(), 2)};
    }
    std::map<std::int64_t, std::uint64_t> counts;
    {
      Stmt s = prepare(db_, name_, "SELECT topic_id, COUNT(*) FROM messages GROUP BY topic_id");
      int rc;
      while ((rc = sqlite3_step(s.get())) == SQLITE_ROW) {
        counts[sqlite3_column_int64(s.get(), 0)] = static_cast<std::uint64_t>(sqlite3_column_int64(s.get(), 1));
        total_ += static_cast<std::uint64_t>(sqlite3_column_int64(s.get(), 1));
      }
      if (rc != SQLITE_DONE) fail(db_, name_, "counting messages");
    }
    Stmt s = prepare(db_, name_, "SELECT id, name, type, serialization_format FROM topics ORDER BY id");
    int rc;
    while ((rc = sqlite3_step(s.get())) == SQLITE_ROW) {
      BagTopic t;
      const std::int64_t id = sqlite3_column_int64(s.get(), 0);
      t.name = text(s.get(), 1);
      t.type = text(s.get(), 2);
      t.serialization_format = text(s.get(), 3);
      const auto d = definitions.find(t.type);
      if (d != definitions.end()) std::tie(t.schema_encoding, t.schema_text) = d->second;
      t.message_count = counts.count(id) ? counts[id] : 0;
      topics_.push_back(std::move(t));
      topic_ids_.push_back(id);
    }
    if (rc != SQLITE_DONE) fail(db_, name_, "reading topics");
  } catch (...) {
    sqlite3_close(db_);
    db_ = nullptr;
    throw;
  }
}

SqliteFileReader::~SqliteFileReader() { sqlite3_close(db_); }

void SqliteFileReader::forEach(const std::set<std::string>& topic_names,
                               const std::function<bool(const BagMessage&)>& fn,
                               const std::function<void(std::uint64_t, std::uint64_t)>& progress) const {
  std::map<std::int64_t, const BagTopic*> wanted;
  for (std::size_t i = 0; i < topics_.size(); ++i)
    if (topic_names.empty() || topic_names.count(topics_[i].name)) wanted[topic_ids_[i]] = &topics_[i];
  if (wanted.empty()) return;
  Stmt s = prepare(db_, name_, "SELECT topic_id, timestamp, data FROM messages ORDER BY timestamp, id");
  std::uint64_t n = 0;
  int rc;
  while ((rc = sqlite3_step(s.get())) == SQLITE_ROW) {
    ++n;
    if (progress && n % 1024 == 0) progress(n, total_);
    const auto t = wanted.find(sqlite3_column_int64(s.get(), 0));
    if (t == wanted.end()) continue;
    BagMessage m;
    m.topic = t->second;
    m.log_time_ns = m.publish_time_ns = sqlite3_column_int64(s.get(), 1);
    const auto* p = static_cast<const std::uint8_t*>(sqlite3_column_blob(s.get(), 2));
    m.data = std::span<const std::uint8_t>(p, p ? static_cast<std::size_t>(sqlite3_column_bytes(s.get(), 2)) : 0);
    if (!fn(m)) return;
  }
  if (rc != SQLITE_DONE) fail(db_, name_, "reading message " + std::to_string(n + 1) + " (in timestamp order)");
  if (progress) progress(total_, total_);
}

SqliteWriter::SqliteWriter(const std::filesystem::path& path) : path_(path), name_(path.string()) {
  if (sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr) != SQLITE_OK) {
    const std::string why = db_ ? sqlite3_errmsg(db_) : "out of memory";
    sqlite3_close(db_);
    db_ = nullptr;
    throw Error("cannot create the SQLite bag: " + why, name_);
  }
  exec("PRAGMA journal_mode=MEMORY");
  exec("PRAGMA synchronous=OFF");
  exec("CREATE TABLE schema(schema_version INTEGER PRIMARY KEY, ros_distro TEXT NOT NULL)");
  exec("INSERT INTO schema VALUES (4, 'rolling')");
  exec("CREATE TABLE metadata(id INTEGER PRIMARY KEY, metadata_version INTEGER NOT NULL, metadata TEXT NOT NULL)");
  exec(
      "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL, "
      "serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL, type_description_hash TEXT NOT NULL)");
  exec(
      "CREATE TABLE message_definitions(id INTEGER PRIMARY KEY, topic_type TEXT NOT NULL, encoding TEXT NOT NULL, "
      "encoded_message_definition TEXT NOT NULL, type_description_hash TEXT NOT NULL)");
  exec(
      "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, timestamp INTEGER NOT NULL, "
      "data BLOB NOT NULL)");
  exec("CREATE INDEX timestamp_idx ON messages (timestamp ASC)");
  exec("BEGIN TRANSACTION");
  insert_ = prepare(db_, name_, "INSERT INTO messages (timestamp, topic_id, data) VALUES (?, ?, ?)").release();
}

SqliteWriter::~SqliteWriter() {
  sqlite3_finalize(insert_);
  sqlite3_close(db_);
}

void SqliteWriter::exec(const char* sql) {
  char* err = nullptr;
  if (sqlite3_exec(db_, sql, nullptr, nullptr, &err) != SQLITE_OK) {
    const std::string why = err ? err : "unknown error";
    sqlite3_free(err);
    throw Error(std::string("SQL '") + sql + "': " + why, name_);
  }
}

std::int64_t SqliteWriter::addTopic(const std::string& name, const std::string& type, const std::string& schema_text) {
  const std::int64_t id = ++topics_;
  Stmt s = prepare(db_, name_, "INSERT INTO topics VALUES (?, ?, ?, 'cdr', '', '')");
  sqlite3_bind_int64(s.get(), 1, id);
  sqlite3_bind_text(s.get(), 2, name.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_text(s.get(), 3, type.c_str(), -1, SQLITE_TRANSIENT);
  if (sqlite3_step(s.get()) != SQLITE_DONE) fail(db_, name_, "adding topic " + name);
  Stmt d = prepare(db_, name_,
                   "INSERT INTO message_definitions (topic_type, encoding, encoded_message_definition, "
                   "type_description_hash) SELECT ?, 'ros2msg', ?, '' WHERE NOT EXISTS "
                   "(SELECT 1 FROM message_definitions WHERE topic_type = ?)");
  sqlite3_bind_text(d.get(), 1, type.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_text(d.get(), 2, schema_text.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_text(d.get(), 3, type.c_str(), -1, SQLITE_TRANSIENT);
  if (sqlite3_step(d.get()) != SQLITE_DONE) fail(db_, name_, "adding the definition of " + type);
  return id;
}

void SqliteWriter::write(std::int64_t topic_id, std::int64_t timestamp_ns, std::span<const std::uint8_t> data) {
  sqlite3_reset(insert_);
  sqlite3_bind_int64(insert_, 1, timestamp_ns);
  sqlite3_bind_int64(insert_, 2, topic_id);
  static const std::uint8_t empty = 0;  // a null pointer would bind NULL, not an empty blob
  sqlite3_bind_blob64(insert_, 3, data.empty() ? &empty : data.data(), data.size(), SQLITE_STATIC);
  if (sqlite3_step(insert_) != SQLITE_DONE) fail(db_, name_, "writing a message");
}

void SqliteWriter::finish() {
  sqlite3_finalize(insert_);
  insert_ = nullptr;
  exec("COMMIT");
  if (sqlite3_close(db_) != SQLITE_OK) fail(db_, name_, "closing");
  db_ = nullptr;
}

}  // namespace glassmap::ros2
