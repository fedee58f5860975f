#pragma once
// MCAP building blocks (https://mcap.dev/spec): the magic, the opcodes, little-endian field
// encoding and a bounds-checked decoder of one record's fields. Private to the io module.

#include <array>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <vector>

#include "glassmap/core/error.hpp"

namespace glassmap::ros2::mcap {

inline constexpr std::array<std::uint8_t, 8> kMagic = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};
inline constexpr std::uint64_t kRecordPrefix = 9;    ///< opcode (1) + content length (8) [bytes]
inline constexpr std::uint64_t kFooterContent = 20;  ///< summary_start, summary_offset_start, summary_crc
inline constexpr std::uint64_t kFooterRecord = kRecordPrefix + kFooterContent;

enum Op : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kAttachment = 0x09,
  kAttachmentIndex = 0x0A,
  kStatistics = 0x0B,
  kMetadata = 0x0C,
  kMetadataIndex = 0x0D,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

/// Name of an opcode for error messages.
const char* opName(std::uint8_t op);

/// CRC-32 (the zlib polynomial, as MCAP uses) of `data`, continuing `crc`.
std::uint32_t crc32(std::uint32_t crc, std::span<const std::uint8_t> data);

inline std::uint64_t loadLe(const std::uint8_t* p, int bytes) {
  std::uint64_t v = 0;
  for (int i = bytes - 1; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}

/// Decodes the fields of one record's content; a field running past the end throws Error naming
/// the file, the record's byte offset and its opcode.
class Fields {
 public:
  Fields(std::span<const std::uint8_t> content, const std::string& file, std::uint64_t record_offset, std::uint8_t op)
      : d_(content), file_(file), offset_(record_offset), op_(op) {}

  std::uint8_t u8() { return static_cast<std::uint8_t>(fixed(1)); }
  std::uint16_t u16() { return static_cast<std::uint16_t>(fixed(2)); }
  std::uint32_t u32() { return static_cast<std::uint32_t>(fixed(4)); }
  std::uint64_t u64() { return fixed(8); }
  std::string str() {
    const auto b = take(u32());
    return std::string(reinterpret_cast<const char*>(b.data()), b.size());
  }
  std::span<const std::uint8_t> bytes32() { return take(u32()); }  ///< uint32 length-prefixed
  std::span<const std::uint8_t> bytes64() { return take(u64()); }  ///< uint64 length-prefixed
  std::span<const std::uint8_t> rest() { return take(d_.size() - p_); }
  std::size_t remaining() const { return d_.size() - p_; }

  /// Throws Error "<file>: byte <offset> (<op> record): <what>".
  [[noreturn]] void fail(const std::string& what) const;

 private:
  std::uint64_t fixed(int n) {
    need(static_cast<std::uint64_t>(n));
    const std::uint64_t v = loadLe(d_.data() + p_, n);
    p_ += static_cast<std::size_t>(n);
    return v;
  }
  std::span<const std::uint8_t> take(std::uint64_t n) {
    need(n);
    auto s = d_.subspan(p_, static_cast<std::size_t>(n));
    p_ += static_cast<std::size_t>(n);
    return s;
  }
  void need(std::uint64_t n) const {
    if (n > d_.size() - p_) fail("a field runs past the end of the record");
  }

  std::span<const std::uint8_t> d_;
  std::size_t p_ = 0;
  const std::string& file_;
  std::uint64_t offset_;
  std::uint8_t op_;
};

/// Little-endian encoder of record contents.
class Buffer {
 public:
  void u8(std::uint8_t v) { b_.push_back(v); }
  void u16(std::uint16_t v) { le(v, 2); }
  void u32(std::uint32_t v) { le(v, 4); }
  void u64(std::uint64_t v) { le(v, 8); }
  void str(const std::string& s) {
    u32(static_cast<std::uint32_t>(s.size()));
    bytes(std::span(reinterpret_cast<const std::uint8_t*>(s.data()), s.size()));
  }
  void bytes(std::span<const std::uint8_t> s) { b_.insert(b_.end(), s.begin(), s.end()); }
  /// Appends a whole record: opcode, content length, content.
  void record(std::uint8_t op, const Buffer& content) {
    u8(op);
    u64(content.size());
    bytes(content.data());
  }
  std::span<const std::uint8_t> data() const { return b_; }
  std::size_t size() const { return b_.size(); }
  void clear() { b_.clear(); }

 private:
  void le(std::uint64_t v, int n) {
    for (int i = 0; i < n; ++i) b_.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  std::vector<std::uint8_t> b_;
};

}  // namespace glassmap::ros2::mcap
