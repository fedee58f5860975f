#include "mcap_reader.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <zlib.h>
#include <algorithm>
#include <cerrno>
#include <cstring>
#include <queue>

#include "glassmap/core/error.hpp"
#include "mcap_compress.hpp"

namespace glassmap::ros2 {

using namespace mcap;

namespace {

std::string at(std::uint64_t offset) { return "byte " + std::to_string(offset); }

// The fields of a Message record (channel id, sequence, log time, publish time, data); `where` is
// the byte of the record (or of the chunk holding it).
McapFileReader::RawMessage messageRecord(Fields& f, std::uint64_t where) {
  McapFileReader::RawMessage m;
  m.channel = f.u16();
  (void)f.u32();  // sequence
  m.log_time = f.u64();
  m.publish_time = f.u64();
  m.data = f.rest();
  m.where = where;
  return m;
}

}  // namespace

const char* mcap::opName(std::uint8_t op) {
  static const char* const names[] = {"unknown",    "Header",        "Footer",          "Schema",
                                      "Channel",    "Message",       "Chunk",           "MessageIndex",
                                      "ChunkIndex", "Attachment",    "AttachmentIndex", "Statistics",
                                      "Metadata",   "MetadataIndex", "SummaryOffset",   "DataEnd"};
  return op <= kDataEnd ? names[op] : "unknown";
}

std::uint32_t mcap::crc32(std::uint32_t crc, std::span<const std::uint8_t> data) {
  while (!data.empty()) {  // zlib takes uInt lengths
    const auto n = static_cast<uInt>(std::min<std::size_t>(data.size(), 1u << 30));
    crc = static_cast<std::uint32_t>(::crc32(crc, data.data(), n));
    data = data.subspan(n);
  }
  return crc;
}

void Fields::fail(const std::string& what) const {
  throw Error(at(offset_) + " (" + opName(op_) + " record): " + what, file_);
}

RandomAccessFile::RandomAccessFile(const std::filesystem::path& path) : name_(path.string()) {
  fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd_ < 0) throw Error(std::string("cannot open: ") + std::strerror(errno), name_);
  struct stat st {};
  if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd_);
    throw Error("not a regular file", name_);
  }
  size_ = static_cast<std::uint64_t>(st.st_size);
}

RandomAccessFile::~RandomAccessFile() {
  if (fd_ >= 0) ::close(fd_);
}

void RandomAccessFile::read(std::uint64_t offset, std::uint64_t n, std::vector<std::uint8_t>& out) const {
  if (offset > size_ || n > size_ - offset)
    throw Error(at(offset) + ": " + std::to_string(n) + " bytes requested past the end of the file", name_);
  out.resize(static_cast<std::size_t>(n));
  std::size_t done = 0;
  while (done < n) {
    const ssize_t r = ::pread(fd_, out.data() + done, n - done, static_cast<off_t>(offset + done));
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0)
      throw Error(at(offset + done) + ": cannot read: " + (r < 0 ? std::strerror(errno) : "file shrank"), name_);
    done += static_cast<std::size_t>(r);
  }
}

McapFileReader::McapFileReader(const std::filesystem::path& path)
    : path_(path), name_(path.string()), file_(std::make_unique<RandomAccessFile>(path)) {
  const std::uint64_t size = file_->size();
  std::vector<std::uint8_t> buf;
  if (size < kMagic.size()) throw Error("not an MCAP file: shorter than the magic", name_);
  file_->read(0, kMagic.size(), buf);
  if (!std::equal(kMagic.begin(), kMagic.end(), buf.begin()))
    throw Error(at(0) + ": not an MCAP file (bad magic)", name_);
  if (size >= kMagic.size() + kRecordPrefix) {
    file_->read(kMagic.size(), kRecordPrefix, buf);
    if (buf[0] != kHeader) throw Error(at(kMagic.size()) + ": the first record is not a Header", name_);
    const std::uint64_t len = loadLe(buf.data() + 1, 8);
    if (len <= size - kMagic.size() - kRecordPrefix) {
      file_->read(kMagic.size() + kRecordPrefix, len, buf);
      Fields f(buf, name_, kMagic.size(), kHeader);
      const std::string profile = f.str(), library = f.str();
      notes_.push_back("MCAP profile '" + profile + "', written by '" + library + "'");
    }
  }

  // Footer and trailing magic; the summary when the footer points to one.
  const std::uint64_t min_size = 2 * kMagic.size() + kRecordPrefix + kFooterRecord;
  if (size >= min_size) {
    const std::uint64_t footer_at = size - kMagic.size() - kFooterRecord;
    file_->read(footer_at, kFooterRecord + kMagic.size(), buf);
    footer_ok_ = buf[0] == kFooter && loadLe(buf.data() + 1, 8) == kFooterContent &&
                 std::equal(kMagic.begin(), kMagic.end(), buf.begin() + kFooterRecord);
    if (footer_ok_) {
      const std::uint64_t summary_start = loadLe(buf.data() + 9, 8), offset_start = loadLe(buf.data() + 17, 8);
      const auto summary_crc = static_cast<std::uint32_t>(loadLe(buf.data() + 25, 4));
      if (summary_start != 0) {
        if (summary_start < kMagic.size() || summary_start > footer_at)
          throw Error(at(footer_at) + " (Footer): summary_start " + std::to_string(summary_start) + " outside the file",
                      name_);
        std::uint64_t summary_end = footer_at;
        if (offset_start != 0) {
          if (offset_start < summary_start || offset_start > footer_at)
            throw Error(at(footer_at) + " (Footer): summary_offset_start outside the summary", name_);
          summary_end = offset_start;
        }
        readSummary(summary_start, summary_end, footer_at, summary_crc);
      }
    }
  }
  // Each chunk once, and no two overlapping: the work of an indexed read stays within the file.
  std::sort(chunks_.begin(), chunks_.end(),
            [](const ChunkIndex& a, const ChunkIndex& b) { return a.offset < b.offset; });
  chunks_.erase(std::unique(chunks_.begin(), chunks_.end(),
                            [](const ChunkIndex& a, const ChunkIndex& b) { return a.offset == b.offset; }),
                chunks_.end());
  for (std::size_t i = 1; i < chunks_.size(); ++i)
    if (chunks_[i].offset < chunks_[i - 1].offset + chunks_[i - 1].length)
      throw Error(at(chunks_[i].offset) + ": the summary's chunk indexes give overlapping chunks", name_);
  indexed_ = !chunks_.empty();
  const bool counted =
      std::any_of(topics_.begin(), topics_.end(), [](const BagTopic& t) { return t.message_count > 0; });
  if (indexed_) {
    notes_.push_back("read through " + std::to_string(chunks_.size()) + " chunk indexes in log-time order");
    if (!counted) {  // no channel_message_counts: count through the chunks (also learns missing channels)
      (void)readIndexed(
          nullptr,
          [&](const RawMessage& m) {
            ++topics_[static_cast<std::size_t>(topicOf(m.channel, m.where))].message_count;
            return true;
          },
          {}, this);
    }
  } else {
    notes_.push_back(footer_ok_ ? "no chunk index: read linearly in file order"
                                : "no footer: read linearly in file order");
    for (auto& t : topics_) t.message_count = 0;
    (void)readLinear(
        [&](const RawMessage& m) {
          ++topics_[static_cast<std::size_t>(topicOf(m.channel, m.where))].message_count;
          return true;
        },
        {}, this);
    if (!truncation_.empty()) notes_.push_back("truncated: " + truncation_);
  }
}

void McapFileReader::readSummary(std::uint64_t start, std::uint64_t end, std::uint64_t footer_at,
                                 std::uint32_t summary_crc) {
  std::vector<std::uint8_t> buf;
  // The CRC covers the summary up to and including the footer's summary_offset_start field.
  file_->read(start, footer_at + kRecordPrefix + 16 - start, buf);
  if (summary_crc != 0 && crc32(0, buf) != summary_crc)
    throw Error(at(start) + ": summary CRC mismatch (footer says " + std::to_string(summary_crc) + ")", name_);
  std::span<const std::uint8_t> s(buf.data(), static_cast<std::size_t>(end - start));
  std::uint64_t pos = 0;
  while (pos < s.size()) {
    const std::uint64_t off = start + pos;
    if (s.size() - pos < kRecordPrefix) throw Error(at(off) + ": summary record cut short", name_);
    const std::uint8_t op = s[pos];
    const std::uint64_t len = loadLe(s.data() + pos + 1, 8);
    if (len > s.size() - pos - kRecordPrefix)
      throw Error(at(off) + " (" + opName(op) + " record): runs past the end of the summary", name_);
    Fields f(s.subspan(pos + kRecordPrefix, len), name_, off, op);
    if (op == kSchema) {
      addSchema(f);
    } else if (op == kChannel) {
      addChannel(f);
    } else if (op == kChunkIndex) {
      ChunkIndex c;
      c.start_time = f.u64();
      c.end_time = f.u64();
      c.offset = f.u64();
      c.length = f.u64();
      Fields map(f.bytes32(), name_, off, op);
      while (map.remaining() > 0) {
        c.channels.push_back(map.u16());
        (void)map.u64();
      }
      if (c.offset < kMagic.size() || c.offset > file_->size() || c.length > file_->size() - c.offset ||
          c.length < kRecordPrefix)
        f.fail("chunk at " + at(c.offset) + " of " + std::to_string(c.length) + " bytes lies outside the file");
      chunks_.push_back(std::move(c));
    } else if (op == kStatistics) {
      const std::uint64_t count = f.u64();
      (void)f.u16();
      for (int i = 0; i < 4; ++i) (void)f.u32();
      (void)f.u64();
      (void)f.u64();
      Fields map(f.bytes32(), name_, off, op);
      while (map.remaining() > 0) {
        const std::uint16_t ch = map.u16();
        const std::uint64_t n = map.u64();
        const auto it = channel_topic_.find(ch);
        if (it != channel_topic_.end()) topics_[static_cast<std::size_t>(it->second)].message_count += n;
      }
      notes_.push_back("statistics: " + std::to_string(count) + " messages");
    }
    pos += kRecordPrefix + len;
  }
}

void McapFileReader::addSchema(Fields& f) {
  const std::uint16_t id = f.u16();
  Schema s;
  s.name = f.str();
  s.encoding = f.str();
  const auto data = f.bytes32();
  s.text.assign(reinterpret_cast<const char*>(data.data()), data.size());
  if (id != 0) schemas_.emplace(id, std::move(s));  // id 0 is invalid: ignored, as the spec says
}

void McapFileReader::addChannel(Fields& f) {
  const std::uint16_t id = f.u16();
  const std::uint16_t schema_id = f.u16();
  BagTopic t;
  t.name = f.str();
  t.serialization_format = f.str();
  (void)f.bytes32();  // metadata (offered QoS profiles in the ros2 profile)
  if (channel_topic_.count(id)) return;
  if (schema_id != 0) {
    const auto s = schemas_.find(schema_id);
    if (s == schemas_.end())
      f.fail("channel " + std::to_string(id) + " refers to unknown schema " + std::to_string(schema_id));
    t.type = s->second.name;
    t.schema_encoding = s->second.encoding;
    t.schema_text = s->second.text;
  }
  const auto same = std::find_if(topics_.begin(), topics_.end(), [&](const BagTopic& o) { return o.name == t.name; });
  if (same != topics_.end()) {
    channel_topic_[id] = static_cast<int>(same - topics_.begin());
  } else {
    channel_topic_[id] = static_cast<int>(topics_.size());
    topics_.push_back(std::move(t));
  }
}

int McapFileReader::topicOf(std::uint16_t channel, std::uint64_t where) const {
  const auto it = channel_topic_.find(channel);
  if (it == channel_topic_.end())
    throw Error(at(where) + ": message on channel " + std::to_string(channel) + ", which no Channel record declares",
                name_);
  return it->second;
}

void McapFileReader::unpackChunk(std::span<const std::uint8_t> content, std::uint64_t offset,
                                 std::vector<std::uint8_t>& out) const {
  Fields f(content, name_, offset, kChunk);
  (void)f.u64();
  (void)f.u64();
  const std::uint64_t usize = f.u64();
  const std::uint32_t ucrc = f.u32();
  const std::string compression = f.str();
  const auto records = f.bytes64();
  decompressBytes(compression, records, usize, out, name_, at(offset) + " (Chunk record)");
  if (ucrc != 0 && crc32(0, out) != ucrc)
    throw Error(at(offset) + " (Chunk record): CRC mismatch of the uncompressed records (record says " +
                    std::to_string(ucrc) + ", data gives " + std::to_string(crc32(0, out)) + ")",
                name_);
}

bool McapFileReader::chunkRecords(std::span<const std::uint8_t> r, std::uint64_t chunk_offset, const Visit& visit,
                                  McapFileReader* learn) const {
  std::size_t pos = 0;
  while (pos < r.size()) {
    const std::string where = at(chunk_offset) + " (Chunk record), record at chunk offset " + std::to_string(pos);
    if (r.size() - pos < kRecordPrefix) throw Error(where + ": cut short", name_);
    const std::uint8_t op = r[pos];
    const std::uint64_t len = loadLe(r.data() + pos + 1, 8);
    if (len > r.size() - pos - kRecordPrefix) throw Error(where + " (" + opName(op) + "): runs past the chunk", name_);
    Fields f(r.subspan(pos + kRecordPrefix, static_cast<std::size_t>(len)), name_, chunk_offset, op);
    if (op == kMessage) {
      if (!visit(messageRecord(f, chunk_offset))) return false;
    } else if (learn && op == kSchema) {
      learn->addSchema(f);
    } else if (learn && op == kChannel) {
      learn->addChannel(f);
    }
    pos += static_cast<std::size_t>(kRecordPrefix + len);
  }
  return true;
}

bool McapFileReader::readLinear(const Visit& visit, const std::function<void(std::uint64_t, std::uint64_t)>& progress,
                                McapFileReader* learn) const {
  const std::uint64_t size = file_->size();
  std::uint64_t pos = kMagic.size();
  std::uint32_t crc = crc32(0, kMagic);
  std::vector<std::uint8_t> rec, chunk;
  const auto truncated = [&](const std::string& why) {
    if (learn) learn->truncation_ = at(pos) + ": " + why + " (truncated file)";
    return true;
  };
  for (std::uint64_t n = 0;; ++n) {
    if (progress && n % 64 == 0) progress(pos, size);
    if (size - pos < kRecordPrefix) return truncated("the file ends before the Data End record");
    file_->read(pos, kRecordPrefix, rec);
    const std::uint8_t op = rec[0];
    const std::uint64_t len = loadLe(rec.data() + 1, 8);
    if (len > size - pos - kRecordPrefix)
      return truncated(std::string(opName(op)) + " record of " + std::to_string(len) + " bytes runs past the end");
    if (op == kFooter) {  // no Data End: a file of the spec's early drafts; fine when the magic follows
      if (!footer_ok_ || pos + kFooterRecord + kMagic.size() != size) return truncated("misplaced Footer");
      return true;
    }
    const std::uint64_t header_crc = crc32(crc, rec);
    file_->read(pos + kRecordPrefix, len, rec);
    Fields f(rec, name_, pos, op);
    if (op == kDataEnd) {
      const std::uint32_t want = f.u32();
      if (want != 0 && want != crc)
        throw Error(at(pos) + " (DataEnd record): data section CRC mismatch (record says " + std::to_string(want) +
                        ", data gives " + std::to_string(crc) + ")",
                    name_);
      if (!footer_ok_) return truncated("the file ends without a Footer and the closing magic");
      return true;
    }
    crc = crc32(static_cast<std::uint32_t>(header_crc), rec);
    if (op == kHeader && pos != kMagic.size()) f.fail("a second Header");
    if (op == kSchema && learn) learn->addSchema(f);
    if (op == kChannel && learn) learn->addChannel(f);
    if (op == kMessage) {
      if (!visit(messageRecord(f, pos))) return false;
    } else if (op == kChunk) {
      unpackChunk(rec, pos, chunk);
      if (!chunkRecords(chunk, pos, visit, learn)) return false;
    }
    pos += kRecordPrefix + len;
  }
}

bool McapFileReader::readIndexed(const std::set<std::uint16_t>* channels, const Visit& visit,
                                 const std::function<void(std::uint64_t, std::uint64_t)>& progress,
                                 McapFileReader* learn) const {
  std::vector<const ChunkIndex*> order;
  for (const auto& c : chunks_) {
    if (channels && !c.channels.empty() &&
        std::none_of(c.channels.begin(), c.channels.end(), [&](std::uint16_t ch) { return channels->count(ch) > 0; }))
      continue;  // the message indexes say: none of the wanted channels in this chunk
    order.push_back(&c);
  }
  std::stable_sort(order.begin(), order.end(), [](const ChunkIndex* a, const ChunkIndex* b) {
    return a->start_time != b->start_time ? a->start_time < b->start_time : a->offset < b->offset;
  });
  struct Pending {
    RawMessage m;
    std::uint64_t seq = 0;  // load order: ties in log time keep file order
    std::shared_ptr<const std::vector<std::uint8_t>> owner;
  };
  const auto later = [](const Pending& a, const Pending& b) {
    return a.m.log_time != b.m.log_time ? a.m.log_time > b.m.log_time : a.seq > b.seq;
  };
  std::priority_queue<Pending, std::vector<Pending>, decltype(later)> heap(later);
  std::uint64_t seq = 0, done = 0;
  std::vector<std::uint8_t> rec;
  std::size_t next = 0;
  for (;;) {
    // Load every chunk that may hold a message earlier than the earliest pending one.
    while (next < order.size() && (heap.empty() || order[next]->start_time <= heap.top().m.log_time)) {
      const ChunkIndex& c = *order[next++];
      file_->read(c.offset, c.length, rec);
      if (rec[0] != kChunk || loadLe(rec.data() + 1, 8) != c.length - kRecordPrefix)
        throw Error(
            at(c.offset) + ": the chunk index points to no Chunk record of " + std::to_string(c.length) + " bytes",
            name_);
      auto data = std::make_shared<std::vector<std::uint8_t>>();
      unpackChunk(std::span(rec).subspan(kRecordPrefix), c.offset, *data);
      (void)chunkRecords(
          *data, c.offset,
          [&](const RawMessage& m) {
            if (!channels || channels->count(m.channel)) heap.push(Pending{m, seq++, data});
            return true;
          },
          learn);
      done += c.length;
      if (progress) progress(done, file_->size());
    }
    if (heap.empty()) return true;
    const Pending p = heap.top();
    heap.pop();
    if (!visit(p.m)) return false;
  }
}

void McapFileReader::forEach(const std::set<std::string>& topic_names, const std::function<bool(const BagMessage&)>& fn,
                             const std::function<void(std::uint64_t, std::uint64_t)>& progress) const {
  std::set<std::uint16_t> wanted;
  for (const auto& [ch, t] : channel_topic_)
    if (topic_names.empty() || topic_names.count(topics_[static_cast<std::size_t>(t)].name)) wanted.insert(ch);
  const auto emit = [&](const RawMessage& m) {
    if (!wanted.count(m.channel)) {
      (void)topicOf(m.channel, m.where);  // an undeclared channel is an error even when filtered out
      return true;
    }
    BagMessage out;
    out.topic = &topics_[static_cast<std::size_t>(channel_topic_.at(m.channel))];
    out.log_time_ns = static_cast<std::int64_t>(m.log_time);
    out.publish_time_ns = static_cast<std::int64_t>(m.publish_time);
    out.data = m.data;
    return fn(out);
  };
  if (indexed_) {
    (void)readIndexed(topic_names.empty() ? nullptr : &wanted, emit, progress, nullptr);
  } else if (readLinear(emit, progress, nullptr) && !truncation_.empty()) {
    throw Error(truncation_, name_);
  }
  if (progress) progress(file_->size(), file_->size());
}

}  // namespace glassmap::ros2
