#pragma once
// Private to io: line-wise reading and writing of plain or gzip text files (CARMEN logs today,
// the text parts of ROS bags later).

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>

struct gzFile_s;

namespace glassmap::io_detail {

/// Closes a zlib file handle.
struct GzCloser {
  void operator()(gzFile_s* f) const;
};
using GzHandle = std::unique_ptr<gzFile_s, GzCloser>;

/// Yields the lines of a plain or gzip file (zlib reads plain files transparently), numbered
/// from 1. Errors (cannot open, corrupt gzip, a line over the cap) throw Error naming the file.
class GzipLineReader {
 public:
  /// Default longest line [bytes]: far above the longest legal log line (1e6 beams and 1e6
  /// remissions of a few characters each), so memory stays bounded on a file without breaks.
  static constexpr std::size_t kDefaultMaxLineBytes = std::size_t{64} << 20;

  explicit GzipLineReader(const std::filesystem::path& path, std::size_t max_line_bytes = kDefaultMaxLineBytes);

  /// Next line without its '\n' (valid until the next call); false at the end of the file.
  bool next(std::string_view& line);

  /// Number of the line last returned by next() (0 before the first).
  std::size_t lineNumber() const { return line_number_; }
  /// Bytes of the file (compressed, as on disk) consumed so far; with fileBytes() a read's progress.
  std::uint64_t fileOffset() const;
  /// Size of the file on disk [bytes] (0 when unknown).
  std::uint64_t fileBytes() const { return file_bytes_; }
  /// The file's name as given, for error messages.
  const std::string& name() const { return name_; }

 private:
  void fill();
  [[noreturn]] void throwZlibError();

  /// Growable byte buffer without zero-filling: only the bytes gzread writes are touched, so
  /// reading a small file costs a page, not the whole buffer.
  struct Buffer {
    std::unique_ptr<char[]> bytes;
    std::size_t capacity = 0;
    char* data() { return bytes.get(); }
    std::size_t size() const { return capacity; }
    void grow(std::size_t n, std::size_t keep);  ///< keeps the first `keep` bytes
  };

  std::string name_;
  std::size_t max_line_bytes_;
  GzHandle file_;
  Buffer buffer_;
  std::size_t pos_ = 0, end_ = 0, line_number_ = 0;
  std::uint64_t file_bytes_ = 0;
  bool eof_ = false;
};

/// Writes text to a file, gzip-compressed when the path ends in ".gz", plain otherwise.
/// Call close() to finish; errors (cannot create, disk full) throw Error naming the file.
class GzipLineWriter {
 public:
  explicit GzipLineWriter(const std::filesystem::path& path);

  /// Appends `text` as it is (the caller adds the '\n's).
  void write(std::string_view text);
  /// Flushes and closes the file; throws when the data could not be written out.
  void close();

 private:
  [[noreturn]] void fail();

  std::string name_;
  GzHandle file_;
};

}  // namespace glassmap::io_detail
