#pragma once
/// ROS 2 bags: the storage containers (rosbag2 directories with metadata.yaml, SQLite .db3 files,
/// MCAP files with uncompressed, zstd or lz4 chunks, with or without a summary section) as a
/// stream of raw messages, and a writer for both storages.
///
/// No MCAP library is packaged in Debian: the reader and writer follow the MCAP specification
/// (https://mcap.dev/spec) directly, decompressing chunks with libzstd and liblz4 (frame format).
/// SQLite bags are read through libsqlite3 (tables `topics` and `messages`; `schema`/`metadata`
/// of newer rosbag2 versions are optional).
///
/// Errors (missing files, bad magic, truncated records, CRC mismatches, unknown compression)
/// throw Error naming the file and the byte offset or record. A truncated MCAP file (one that
/// does not end in a Footer and the closing magic, e.g. a recording that was killed) opens, and
/// forEach delivers every complete message before it throws Error naming the byte where the data
/// stops; a file lacking only the summary is legal and read linearly without error. Lengths in a
/// file never allocate more than the file (or, for compressed chunks, max(64 MiB, 256 × the
/// compressed size)) can justify.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <set>
#include <span>
#include <string>
#include <vector>

namespace glassmap::ros2 {

/// A topic of a bag, as the storage declares it.
struct BagTopic {
  std::string name;                  ///< e.g. "/scan"
  std::string type;                  ///< e.g. "sensor_msgs/msg/LaserScan"
  std::string serialization_format;  ///< "cdr" for every bag ros2 bag record writes
  std::string schema_encoding;       ///< MCAP schema encoding ("ros2msg", "ros2idl", ...); "" when not given
  std::string schema_text;           ///< the message definition the bag carries; "" when not given
  std::uint64_t message_count = 0;   ///< messages on this topic (from the index/summary, else counted)
};

/// One serialized message. `data` is valid only during the callback.
struct BagMessage {
  const BagTopic* topic = nullptr;
  std::int64_t log_time_ns = 0;      ///< receive/record time [ns since epoch]
  std::int64_t publish_time_ns = 0;  ///< publish time [ns]; = log_time_ns where the storage has none
  std::span<const std::uint8_t> data;
};

/// Storage plugin names as rosbag2 writes them in metadata.yaml.
enum class BagStorage { Sqlite3, Mcap };
/// MCAP chunk compression.
enum class BagCompression { None, Zstd, Lz4 };

/// An opened bag: a directory with metadata.yaml (every file it lists, in order), or a single
/// .db3 or .mcap file (told apart by content: the MCAP magic or the SQLite header).
class BagReader {
 public:
  virtual ~BagReader() = default;
  /// Every topic of the bag (all files merged by name).
  virtual const std::vector<BagTopic>& topics() const = 0;
  /// Calls `fn` for every message on a topic in `topic_names` (all topics when empty), in
  /// log-time order (files in order; an MCAP with a message index is read in log-time order,
  /// one without a summary linearly in file order). `fn` returns false to stop early.
  /// `progress`, when given, is called now and then with the bytes read so far and the total.
  virtual void forEach(const std::set<std::string>& topic_names, const std::function<bool(const BagMessage&)>& fn,
                       const std::function<void(std::uint64_t done, std::uint64_t total)>& progress = {}) const = 0;
  /// Storage of the (first) file.
  virtual BagStorage storage() const = 0;
  /// The files read, in order.
  virtual std::vector<std::filesystem::path> files() const = 0;
  /// What the reader found or assumed, one line each (MCAP profile and read mode, SQLite schema
  /// version, compression, a truncation), for `info`-like reports.
  virtual std::vector<std::string> notes() const { return {}; }
};

/// True when `path` looks like a bag: a directory holding metadata.yaml, or a file starting with
/// the MCAP magic or "SQLite format 3\0". Never throws for a missing path (false).
bool isBag(const std::filesystem::path& path);

/// Opens a bag (see BagReader); throws Error when it cannot be read.
std::unique_ptr<BagReader> openBag(const std::filesystem::path& path);

/// Options of the writer.
struct BagWriteOptions {
  BagStorage storage = BagStorage::Mcap;
  BagCompression compression = BagCompression::Zstd;  ///< MCAP only
  std::uint64_t chunk_size = 1 << 20;                 ///< MCAP chunk size before compression [bytes]
  bool write_summary = true;                          ///< MCAP: summary section, chunk and message indexes
};

/// Writes a rosbag2 bag: `path` is the bag directory (created; must not exist or be empty), which
/// gets `<dirname>_0.mcap` or `<dirname>_0.db3` and metadata.yaml (rosbag2 version 5 layout).
/// Written into a temporary sibling directory and renamed when close() succeeds.
class BagWriter {
 public:
  BagWriter(const std::filesystem::path& path, const BagWriteOptions& options = {});
  ~BagWriter();  ///< without close(): removes the temporary directory
  BagWriter(const BagWriter&) = delete;
  BagWriter& operator=(const BagWriter&) = delete;
  /// Declares a topic with its type and ROS 2 message definition (ros2msg text); returns its id.
  int addTopic(const std::string& name, const std::string& type, const std::string& schema_text);
  /// Appends one serialized (CDR) message; log times need not be sorted.
  void write(int topic_id, std::int64_t log_time_ns, std::span<const std::uint8_t> cdr);
  /// Finishes the files and metadata.yaml, and moves the bag into place.
  void close();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace glassmap::ros2
