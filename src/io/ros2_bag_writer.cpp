// BagWriter: a rosbag2 directory (<name>_0.mcap or <name>_0.db3 + metadata.yaml, version 5
// layout) written into a temporary sibling folder and renamed into place by close().

#include <algorithm>
#include <fstream>
#include <limits>

#include <yaml-cpp/yaml.h>

#include "glassmap/core/atomic_file.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/io/ros2_bag.hpp"
#include "mcap_writer.hpp"
#include "sqlite_bag.hpp"

namespace glassmap::ros2 {

namespace fs = std::filesystem;

struct BagWriter::Impl {
  fs::path target, staging, file;
  BagWriteOptions options;
  std::unique_ptr<LiveTemporary> live;
  std::unique_ptr<McapWriter> mcap;
  std::unique_ptr<SqliteWriter> sqlite;
  struct Topic {
    std::string name, type;
    std::uint16_t channel = 0;
    std::int64_t sqlite_id = 0;
    std::uint64_t count = 0;
  };
  std::vector<Topic> topics;
  std::int64_t start = 0, end = 0;
  std::uint64_t count = 0;
  bool closed = false;

  void writeMetadata(const fs::path& path) const;
};

BagWriter::BagWriter(const fs::path& path, const BagWriteOptions& options) : impl_(std::make_unique<Impl>()) {
  Impl& w = *impl_;
  w.target = path.filename().empty() ? path.parent_path() : path;
  w.options = options;
  std::error_code ec;
  if (fs::exists(w.target, ec) && !(fs::is_directory(w.target, ec) && fs::is_empty(w.target, ec)))
    throw Error("the bag folder exists and is not empty", w.target.string());
  const fs::path parent = w.target.has_parent_path() ? w.target.parent_path() : fs::path(".");
  checkWritableDirectory(parent);
  fs::create_directories(parent, ec);
  w.staging = temporarySibling(w.target);
  w.live = std::make_unique<LiveTemporary>(w.staging, /*is_directory=*/true);
  if (!fs::create_directory(w.staging, ec) || ec)
    throw Error("cannot create a staging folder: " + ec.message(), w.target.string());
  const std::string stem = w.target.filename().string() + "_0";
  try {
    if (options.storage == BagStorage::Mcap) {
      w.file = stem + ".mcap";
      w.mcap = std::make_unique<McapWriter>(w.staging / w.file, options.compression, options.chunk_size,
                                            options.write_summary);
    } else {
      w.file = stem + ".db3";
      w.sqlite = std::make_unique<SqliteWriter>(w.staging / w.file);
    }
  } catch (...) {
    fs::remove_all(w.staging, ec);
    throw;
  }
}

BagWriter::~BagWriter() {
  if (!impl_->closed) {
    impl_->mcap.reset();
    impl_->sqlite.reset();
    std::error_code ec;
    fs::remove_all(impl_->staging, ec);
  }
}

int BagWriter::addTopic(const std::string& name, const std::string& type, const std::string& schema_text) {
  Impl& w = *impl_;
  if (w.closed) throw Error("addTopic after close()", w.target.string());
  if (std::any_of(w.topics.begin(), w.topics.end(), [&](const Impl::Topic& t) { return t.name == name; }))
    throw Error("topic " + name + " added twice", w.target.string());
  Impl::Topic t{name, type};
  if (w.mcap) t.channel = w.mcap->addChannel(name, type, schema_text);
  if (w.sqlite) t.sqlite_id = w.sqlite->addTopic(name, type, schema_text);
  w.topics.push_back(std::move(t));
  return static_cast<int>(w.topics.size() - 1);
}

void BagWriter::write(int topic_id, std::int64_t log_time_ns, std::span<const std::uint8_t> cdr) {
  Impl& w = *impl_;
  if (w.closed) throw Error("write after close()", w.target.string());
  if (topic_id < 0 || static_cast<std::size_t>(topic_id) >= w.topics.size())
    throw Error("write to unknown topic id " + std::to_string(topic_id), w.target.string());
  if (log_time_ns < 0) throw Error("negative log time " + std::to_string(log_time_ns), w.target.string());
  Impl::Topic& t = w.topics[static_cast<std::size_t>(topic_id)];
  if (w.mcap) {
    const auto ns = static_cast<std::uint64_t>(log_time_ns);
    w.mcap->write(t.channel, ns, ns, cdr);
  } else {
    w.sqlite->write(t.sqlite_id, log_time_ns, cdr);
  }
  ++t.count;
  w.start = w.count ? std::min(w.start, log_time_ns) : log_time_ns;
  w.end = w.count ? std::max(w.end, log_time_ns) : log_time_ns;
  ++w.count;
}

void BagWriter::Impl::writeMetadata(const fs::path& path) const {
  YAML::Emitter y;
  const auto ns = [&](const char* key, const char* sub, std::int64_t v) {
    y << YAML::Key << key << YAML::Value << YAML::BeginMap << YAML::Key << sub << YAML::Value << v << YAML::EndMap;
  };
  y << YAML::BeginMap << YAML::Key << "rosbag2_bagfile_information" << YAML::Value << YAML::BeginMap;
  y << YAML::Key << "version" << YAML::Value << 5;
  y << YAML::Key << "storage_identifier" << YAML::Value << (mcap ? "mcap" : "sqlite3");
  ns("duration", "nanoseconds", end - start);
  ns("starting_time", "nanoseconds_since_epoch", start);
  y << YAML::Key << "message_count" << YAML::Value << count;
  y << YAML::Key << "topics_with_message_count" << YAML::Value << YAML::BeginSeq;
  for (const Topic& t : topics) {
    y << YAML::BeginMap << YAML::Key << "topic_metadata" << YAML::Value << YAML::BeginMap;
    y << YAML::Key << "name" << YAML::Value << t.name << YAML::Key << "type" << YAML::Value << t.type;
    y << YAML::Key << "serialization_format" << YAML::Value << "cdr";
    y << YAML::Key << "offered_qos_profiles" << YAML::Value << YAML::DoubleQuoted << "" << YAML::EndMap;
    y << YAML::Key << "message_count" << YAML::Value << t.count << YAML::EndMap;
  }
  y << YAML::EndSeq;
  y << YAML::Key << "compression_format" << YAML::Value << YAML::DoubleQuoted << "";
  y << YAML::Key << "compression_mode" << YAML::Value << YAML::DoubleQuoted << "";
  y << YAML::Key << "relative_file_paths" << YAML::Value << YAML::BeginSeq << file.string() << YAML::EndSeq;
  y << YAML::Key << "files" << YAML::Value << YAML::BeginSeq << YAML::BeginMap;
  y << YAML::Key << "path" << YAML::Value << file.string();
  ns("starting_time", "nanoseconds_since_epoch", start);
  ns("duration", "nanoseconds", end - start);
  y << YAML::Key << "message_count" << YAML::Value << count << YAML::EndMap << YAML::EndSeq;
  y << YAML::EndMap << YAML::EndMap;
  std::ofstream out(path, std::ios::binary);
  out << y.c_str() << "\n";
  out.close();
  if (!out) throw Error("cannot write", path.string());
}

void BagWriter::close() {
  Impl& w = *impl_;
  if (w.closed) return;
  std::error_code ec;
  try {
    if (w.mcap) w.mcap->finish();
    if (w.sqlite) w.sqlite->finish();
    w.writeMetadata(w.staging / "metadata.yaml");
    syncToDisk(w.staging / w.file);
    syncToDisk(w.staging / "metadata.yaml");
    if (fs::exists(w.target, ec)) fs::remove(w.target, ec);  // the empty folder the caller may have made
    fs::rename(w.staging, w.target, ec);
    if (ec) throw Error("cannot move the bag into place: " + ec.message(), w.target.string());
  } catch (const Error& e) {
    fs::remove_all(w.staging, ec);
    w.closed = true;
    throw Error(e.message(),
                w.target.string() + (e.file().empty() ? "" : " (" + fs::path(e.file()).filename().string() + ")"),
                e.line(), e.field());
  }
  w.closed = true;
  w.live.reset();
}

}  // namespace glassmap::ros2
