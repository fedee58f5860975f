#pragma once
// MCAP file reader (https://mcap.dev/spec). Private to the io module; use openBag().
//
// With a summary holding chunk indexes, messages are read chunk by chunk in log-time order (a
// merge across overlapping chunks; chunks without a wanted channel are skipped). Without one,
// the file is read linearly in file order (an open pass learns the channels and counts).
// Truncated input (a file not ending in Footer + magic): the complete messages are delivered,
// then forEach throws Error naming the file and the byte offset where the data stops.

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "glassmap/io/ros2_bag.hpp"
#include "mcap_format.hpp"

namespace glassmap::ros2 {

/// Reads ranges of a file with pread; errors name the file.
class RandomAccessFile {
 public:
  explicit RandomAccessFile(const std::filesystem::path& path);
  ~RandomAccessFile();
  RandomAccessFile(const RandomAccessFile&) = delete;
  RandomAccessFile& operator=(const RandomAccessFile&) = delete;
  std::uint64_t size() const { return size_; }
  /// Reads exactly `n` bytes at `offset` into `out` (resized); the range must lie in the file.
  void read(std::uint64_t offset, std::uint64_t n, std::vector<std::uint8_t>& out) const;
  const std::string& name() const { return name_; }

 private:
  int fd_ = -1;
  std::uint64_t size_ = 0;
  std::string name_;
};

class McapFileReader final : public BagReader {
 public:
  explicit McapFileReader(const std::filesystem::path& path);
  const std::vector<BagTopic>& topics() const override { return topics_; }
  void forEach(const std::set<std::string>& topic_names, const std::function<bool(const BagMessage&)>& fn,
               const std::function<void(std::uint64_t, std::uint64_t)>& progress = {}) const override;
  BagStorage storage() const override { return BagStorage::Mcap; }
  std::vector<std::filesystem::path> files() const override { return {path_}; }
  std::vector<std::string> notes() const override { return notes_; }

  struct ChunkIndex {
    std::uint64_t start_time = 0, end_time = 0, offset = 0, length = 0;
    std::vector<std::uint16_t> channels;  ///< from message_index_offsets; empty: unknown
  };
  struct RawMessage {
    std::uint16_t channel = 0;
    std::uint64_t log_time = 0, publish_time = 0;
    std::uint64_t where = 0;  ///< byte offset of the record (of its chunk, for chunked messages)
    std::span<const std::uint8_t> data;
  };
  /// Visits messages; returns false to stop.
  using Visit = std::function<bool(const RawMessage&)>;

 private:
  void readSummary(std::uint64_t summary_start, std::uint64_t summary_end, std::uint64_t footer_at,
                   std::uint32_t summary_crc);
  void addSchema(mcap::Fields& f);
  void addChannel(mcap::Fields& f);
  /// Parses the records of a chunk's uncompressed `records`; calls visit for its messages.
  /// Schemas and channels are registered through `learn` (the open pass), else skipped.
  bool chunkRecords(std::span<const std::uint8_t> records, std::uint64_t chunk_offset, const Visit& visit,
                    McapFileReader* learn) const;
  /// Loads the chunk record at `offset` (content `content`), checks and decompresses it.
  void unpackChunk(std::span<const std::uint8_t> content, std::uint64_t offset, std::vector<std::uint8_t>& out) const;
  /// Linear pass; returns false when visit stopped it. Sets truncation_ instead of throwing when
  /// the data stops early.
  bool readLinear(const Visit& visit, const std::function<void(std::uint64_t, std::uint64_t)>& progress,
                  McapFileReader* learn) const;
  bool readIndexed(const std::set<std::uint16_t>* channels, const Visit& visit,
                   const std::function<void(std::uint64_t, std::uint64_t)>& progress, McapFileReader* learn) const;
  int topicOf(std::uint16_t channel, std::uint64_t where) const;

  std::filesystem::path path_;
  std::string name_;
  std::unique_ptr<RandomAccessFile> file_;
  struct Schema {
    std::string name, encoding, text;
  };
  std::map<std::uint16_t, Schema> schemas_;
  std::map<std::uint16_t, int> channel_topic_;  ///< channel id → index in topics_
  std::vector<BagTopic> topics_;
  std::vector<ChunkIndex> chunks_;
  bool indexed_ = false;
  bool footer_ok_ = false;
  std::string truncation_;  ///< set by the linear pass: why and where the data stops early
  std::vector<std::string> notes_;
};

}  // namespace glassmap::ros2
