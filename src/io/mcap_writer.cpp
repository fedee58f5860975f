#include "mcap_writer.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "glassmap/core/error.hpp"
#include "mcap_compress.hpp"

namespace glassmap::ros2 {

using namespace mcap;

McapWriter::McapWriter(const std::filesystem::path& path, BagCompression compression, std::uint64_t chunk_size,
                       bool write_summary)
    : path_(path),
      compression_(compression),
      chunk_size_(std::max<std::uint64_t>(chunk_size, 1)),
      summary_(write_summary) {
  file_ = std::fopen(path.c_str(), "wb");
  if (!file_) throw Error(std::string("cannot create: ") + std::strerror(errno), path.string());
  out(kMagic);
  Buffer header, rec;
  header.str("ros2");
  header.str("glassmap");
  rec.record(kHeader, header);
  out(rec.data());
}

McapWriter::~McapWriter() {
  if (file_) std::fclose(file_);
}

void McapWriter::out(std::span<const std::uint8_t> bytes) {
  if (bytes.empty()) return;  // an empty summary: fwrite must not see its null pointer
  if (std::fwrite(bytes.data(), 1, bytes.size(), file_) != bytes.size())
    throw Error(std::string("cannot write: ") + std::strerror(errno), path_.string());
  if (in_data_) data_crc_ = crc32(data_crc_, bytes);
  offset_ += bytes.size();
}

std::uint16_t McapWriter::addChannel(const std::string& topic, const std::string& type,
                                     const std::string& schema_text) {
  if (sequence_.size() >= 0xFFFF) throw Error("more than 65535 topics", path_.string());
  auto [it, added] = schema_ids_.emplace(type, static_cast<std::uint16_t>(schema_ids_.size() + 1));
  if (added) {
    Buffer s;
    s.u16(it->second);
    s.str(type);
    s.str("ros2msg");
    s.str(schema_text);
    chunk_.record(kSchema, s);
    schemas_.record(kSchema, s);
  }
  sequence_.push_back(0);
  const auto id = static_cast<std::uint16_t>(sequence_.size());
  Buffer c;
  c.u16(id);
  c.u16(it->second);
  c.str(topic);
  c.str("cdr");
  Buffer meta;  // the ros2 profile's channel metadata; the QoS profiles are not known here
  meta.str("offered_qos_profiles");
  meta.str("");
  c.u32(static_cast<std::uint32_t>(meta.size()));
  c.bytes(meta.data());
  chunk_.record(kChannel, c);
  channels_.record(kChannel, c);
  return id;
}

void McapWriter::write(std::uint16_t channel, std::uint64_t log_time, std::uint64_t publish_time,
                       std::span<const std::uint8_t> data) {
  if (channel == 0 || channel > sequence_.size())
    throw Error("write to undeclared channel " + std::to_string(channel), path_.string());
  if (chunk_has_messages_) {
    chunk_start_ = std::min(chunk_start_, log_time);
    chunk_end_ = std::max(chunk_end_, log_time);
  } else {
    chunk_start_ = chunk_end_ = log_time;
    chunk_has_messages_ = true;
  }
  start_ = message_count_ ? std::min(start_, log_time) : log_time;
  end_ = message_count_ ? std::max(end_, log_time) : log_time;
  ++message_count_;
  ++channel_counts_[channel];
  chunk_index_[channel].emplace_back(log_time, chunk_.size());
  chunk_.u8(kMessage);
  chunk_.u64(2 + 4 + 8 + 8 + data.size());
  chunk_.u16(channel);
  chunk_.u32(sequence_[channel - 1u]++);
  chunk_.u64(log_time);
  chunk_.u64(publish_time);
  chunk_.bytes(data);
  if (chunk_.size() >= chunk_size_) flushChunk();
}

void McapWriter::flushChunk() {
  if (chunk_.size() == 0) return;
  const std::vector<std::uint8_t> packed = compressBytes(compression_, chunk_.data());
  Buffer c, rec;
  c.u64(chunk_has_messages_ ? chunk_start_ : 0);
  c.u64(chunk_has_messages_ ? chunk_end_ : 0);
  c.u64(chunk_.size());
  c.u32(crc32(0, chunk_.data()));
  c.str(compressionName(compression_));
  c.u64(packed.size());
  c.bytes(packed);
  rec.record(kChunk, c);
  const std::uint64_t chunk_offset = offset_;
  out(rec.data());
  const std::uint64_t chunk_length = rec.size();

  Buffer offsets;  // Map<uint16, uint64>: channel → offset of its message index record
  const std::uint64_t index_start = offset_;
  if (summary_) {
    Buffer indexes;
    for (const auto& [ch, entries] : chunk_index_) {
      offsets.u16(ch);
      offsets.u64(offset_ + indexes.size());
      Buffer m;
      m.u16(ch);
      m.u32(static_cast<std::uint32_t>(entries.size() * 16));
      for (const auto& [t, o] : entries) {
        m.u64(t);
        m.u64(o);
      }
      indexes.record(kMessageIndex, m);
    }
    out(indexes.data());
  }
  Buffer ci;
  ci.u64(chunk_has_messages_ ? chunk_start_ : 0);
  ci.u64(chunk_has_messages_ ? chunk_end_ : 0);
  ci.u64(chunk_offset);
  ci.u64(chunk_length);
  ci.u32(static_cast<std::uint32_t>(offsets.size()));
  ci.bytes(offsets.data());
  ci.u64(offset_ - index_start);
  ci.str(compressionName(compression_));
  ci.u64(packed.size());
  ci.u64(chunk_.size());
  chunk_indexes_.record(kChunkIndex, ci);
  ++chunk_count_;
  chunk_.clear();
  chunk_index_.clear();
  chunk_has_messages_ = false;
}

void McapWriter::finish() {
  flushChunk();
  in_data_ = false;
  Buffer de, rec;
  de.u32(data_crc_);
  rec.record(kDataEnd, de);
  out(rec.data());

  std::uint64_t summary_start = 0, offset_start = 0;
  Buffer summary;
  if (summary_) {
    summary_start = offset_;
    struct Group {
      std::uint8_t op;
      std::uint64_t start, length;
    };
    std::vector<Group> groups;
    const auto group = [&](std::uint8_t op, const Buffer& records) {
      if (records.size() == 0) return;
      groups.push_back({op, summary_start + summary.size(), records.size()});
      summary.bytes(records.data());
    };
    group(kSchema, schemas_);
    group(kChannel, channels_);
    Buffer st, st_rec;
    st.u64(message_count_);
    st.u16(static_cast<std::uint16_t>(schema_ids_.size()));
    st.u32(static_cast<std::uint32_t>(sequence_.size()));
    st.u32(0);  // attachments
    st.u32(0);  // metadata
    st.u32(chunk_count_);
    st.u64(start_);
    st.u64(end_);
    st.u32(static_cast<std::uint32_t>(channel_counts_.size() * 10));
    for (const auto& [ch, n] : channel_counts_) {
      st.u16(ch);
      st.u64(n);
    }
    st_rec.record(kStatistics, st);
    group(kStatistics, st_rec);
    group(kChunkIndex, chunk_indexes_);
    offset_start = summary_start + summary.size();
    for (const Group& g : groups) {
      Buffer so;
      so.u8(g.op);
      so.u64(g.start);
      so.u64(g.length);
      summary.record(kSummaryOffset, so);
    }
  }
  Buffer footer;
  footer.u8(kFooter);
  footer.u64(kFooterContent);
  footer.u64(summary_start);
  footer.u64(offset_start);
  footer.u32(summary_ ? crc32(crc32(0, summary.data()), footer.data()) : 0);
  out(summary.data());
  out(footer.data());
  out(kMagic);
  const int flushed = std::fflush(file_);
  const int closed = std::fclose(file_);
  file_ = nullptr;
  if (flushed != 0 || closed != 0) throw Error(std::string("cannot write: ") + std::strerror(errno), path_.string());
}

}  // namespace glassmap::ros2
