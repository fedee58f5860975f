#include "gzip_lines.hpp"

#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "glassmap/core/error.hpp"

namespace glassmap::io_detail {

void GzCloser::operator()(gzFile_s* f) const { gzclose(f); }

// ---------------------------------------------------------------------------------------------
// Reading

void GzipLineReader::Buffer::grow(std::size_t n, std::size_t keep) {
  auto bigger = std::make_unique_for_overwrite<char[]>(n);
  if (keep) std::memcpy(bigger.get(), bytes.get(), keep);
  bytes = std::move(bigger);
  capacity = n;
}

GzipLineReader::GzipLineReader(const std::filesystem::path& path, std::size_t max_line_bytes)
    : name_(path.string()), max_line_bytes_(max_line_bytes) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  file_bytes_ = ec ? 0 : static_cast<std::uint64_t>(size);
  file_.reset(gzopen(name_.c_str(), "rb"));
  if (!file_) {
    const int err = errno;
    throw Error(std::string("cannot open: ") + (err ? std::strerror(err) : "out of memory"), name_);
  }
  gzbuffer(file_.get(), 1 << 17);
  buffer_.grow(1 << 18, 0);
}

bool GzipLineReader::next(std::string_view& line) {
  for (;;) {
    const char* begin = buffer_.data() + pos_;
    const char* nl = static_cast<const char*>(std::memchr(begin, '\n', end_ - pos_));
    if (nl) {
      line = std::string_view(begin, static_cast<std::size_t>(nl - begin));
      pos_ = static_cast<std::size_t>(nl - buffer_.data()) + 1;
      ++line_number_;
      return true;
    }
    if (eof_) {
      if (pos_ == end_) return false;
      line = std::string_view(begin, end_ - pos_);
      pos_ = end_;
      ++line_number_;
      return true;
    }
    fill();
  }
}

std::uint64_t GzipLineReader::fileOffset() const {
  const auto offset = gzoffset(file_.get());
  return offset < 0 ? 0 : std::min<std::uint64_t>(static_cast<std::uint64_t>(offset), file_bytes_);
}

void GzipLineReader::fill() {
  // Keep the unfinished line at the front, grow when one line exceeds the buffer.
  const std::size_t rest = end_ - pos_;
  if (pos_ > 0) std::memmove(buffer_.data(), buffer_.data() + pos_, rest);
  pos_ = 0;
  end_ = rest;
  if (end_ == buffer_.size()) {
    if (buffer_.size() >= max_line_bytes_)
      throw Error("line longer than " + std::to_string(max_line_bytes_ >> 20) + " MiB (not a text log?)", name_,
                  line_number_ + 1);
    buffer_.grow(buffer_.size() * 2, end_);
  }
  const int n = gzread(file_.get(), buffer_.data() + end_, static_cast<unsigned>(buffer_.size() - end_));
  if (n < 0) throwZlibError();
  if (n == 0) {
    int errnum = Z_OK;
    gzerror(file_.get(), &errnum);
    if (errnum != Z_OK && errnum != Z_STREAM_END) throwZlibError();
    eof_ = true;
  }
  end_ += static_cast<std::size_t>(n);
}

void GzipLineReader::throwZlibError() {
  int errnum = Z_OK;
  const char* msg = gzerror(file_.get(), &errnum);
  std::string text = errnum == Z_ERRNO ? std::strerror(errno) : (msg ? msg : "unknown zlib error");
  throw Error("corrupt or truncated gzip data after line " + std::to_string(line_number_) + " (" + text + ")", name_);
}

// ---------------------------------------------------------------------------------------------
// Writing

GzipLineWriter::GzipLineWriter(const std::filesystem::path& path) : name_(path.string()) {
  const bool compress = path.extension() == ".gz";
  file_.reset(gzopen(name_.c_str(), compress ? "wb6" : "wbT"));
  if (!file_) throw Error(std::string("cannot create: ") + std::strerror(errno), name_);
}

void GzipLineWriter::write(std::string_view text) {
  if (text.empty()) return;
  if (gzwrite(file_.get(), text.data(), static_cast<unsigned>(text.size())) != static_cast<int>(text.size())) fail();
}

void GzipLineWriter::close() {
  if (gzclose(file_.release()) != Z_OK) throw Error("cannot finish writing (disk full?)", name_);
}

void GzipLineWriter::fail() {
  int errnum = Z_OK;
  const char* msg = gzerror(file_.get(), &errnum);
  throw Error(std::string("write failed: ") + (errnum == Z_ERRNO ? std::strerror(errno) : msg), name_);
}

}  // namespace glassmap::io_detail
