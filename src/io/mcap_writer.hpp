#pragma once
// MCAP file writer (https://mcap.dev/spec), ros2 profile: schemas in `ros2msg`, messages in
// `cdr`, chunked with none/zstd/lz4 compression, optionally message indexes and a summary
// (schemas, channels, statistics, chunk indexes, summary offsets). Private to the io module.

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "glassmap/io/ros2_bag.hpp"
#include "mcap_format.hpp"

namespace glassmap::ros2 {

class McapWriter {
 public:
  /// Creates `path` (truncating it) and writes the magic and the Header.
  McapWriter(const std::filesystem::path& path, BagCompression compression, std::uint64_t chunk_size,
             bool write_summary);
  ~McapWriter();  ///< closes the file without finishing it
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;

  /// Declares a channel on `topic` with a schema for `type` (one schema per type); returns its id.
  std::uint16_t addChannel(const std::string& topic, const std::string& type, const std::string& schema_text);
  /// Appends a message; log times may come in any order.
  void write(std::uint16_t channel, std::uint64_t log_time, std::uint64_t publish_time,
             std::span<const std::uint8_t> data);
  /// Flushes the last chunk, writes Data End, the summary, the Footer and the closing magic.
  void finish();

 private:
  void out(std::span<const std::uint8_t> bytes);
  void flushChunk();

  std::filesystem::path path_;
  std::FILE* file_ = nullptr;
  BagCompression compression_;
  std::uint64_t chunk_size_;
  bool summary_;
  std::uint64_t offset_ = 0;         ///< bytes written
  std::uint32_t data_crc_ = 0;       ///< CRC of everything written before Data End
  bool in_data_ = true;              ///< still in the data section (the CRC runs)
  mcap::Buffer schemas_, channels_;  ///< summary copies of the Schema and Channel records
  std::map<std::string, std::uint16_t> schema_ids_;
  std::vector<std::uint32_t> sequence_;  ///< per channel (index id - 1)
  // Current chunk.
  mcap::Buffer chunk_;
  std::uint64_t chunk_start_ = 0, chunk_end_ = 0;
  bool chunk_has_messages_ = false;
  std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>>
      chunk_index_;  ///< channel → (time, offset)
  // Totals.
  mcap::Buffer chunk_indexes_;
  std::uint32_t chunk_count_ = 0;
  std::uint64_t message_count_ = 0, start_ = 0, end_ = 0;
  std::map<std::uint16_t, std::uint64_t> channel_counts_;
};

}  // namespace glassmap::ros2
