#include "glassmap/core/scan_spool.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <string>

#include "glassmap/core/error.hpp"

namespace glassmap {
namespace {

// A record: the scan's numbers, then its ranges. Written and read on one machine, in its byte order.
struct RecordHead {
  double timestamp, start_angle, angular_step, max_range;
  double laser[3], odom[3];  // x, y, theta
  std::int32_t laser_id;
  std::uint8_t has_odom, has_laser_pose, pad[2];
  std::uint64_t beams;
};
static_assert(sizeof(RecordHead) == 96);

constexpr std::size_t kWriteBuffer = 4u << 20;  // appended bytes held before a write [bytes]

std::string reason() { return std::strerror(errno); }

}  // namespace

ScanSpool::ScanSpool(const std::filesystem::path& directory) : directory_(directory) {
  // An unnamed file in the folder where the system supports it, else a named one unlinked at once.
  fd_ = ::open(directory.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
  if (fd_ < 0) {
    std::string name = (directory / ".glassmap-scans-XXXXXX").string();
    fd_ = ::mkostemp(name.data(), O_CLOEXEC);
    if (fd_ < 0)
      throw Error("cannot make a temporary file for the scans that do not fit in memory: " + reason(),
                  directory.string());
    ::unlink(name.c_str());
  }
  buffer_.reserve(kWriteBuffer);
}

ScanSpool::~ScanSpool() {
  if (fd_ >= 0) ::close(fd_);
}

void ScanSpool::append(const LaserScan& s) {
  RecordHead h{};
  h.timestamp = s.timestamp;
  h.start_angle = s.start_angle;
  h.angular_step = s.angular_step;
  h.max_range = s.max_range;
  h.laser[0] = s.laser_pose.t.x(), h.laser[1] = s.laser_pose.t.y(), h.laser[2] = s.laser_pose.theta;
  h.odom[0] = s.odom_pose.t.x(), h.odom[1] = s.odom_pose.t.y(), h.odom[2] = s.odom_pose.theta;
  h.laser_id = s.laser_id;
  h.has_odom = s.has_odom ? 1 : 0;
  h.has_laser_pose = s.has_laser_pose ? 1 : 0;
  h.beams = s.ranges.size();
  const auto* head = reinterpret_cast<const unsigned char*>(&h);
  const auto* ranges = reinterpret_cast<const unsigned char*>(s.ranges.data());
  buffer_.insert(buffer_.end(), head, head + sizeof h);
  buffer_.insert(buffer_.end(), ranges, ranges + s.ranges.size() * sizeof(float));
  ++count_;
  if (buffer_.size() >= kWriteBuffer) flush();
}

void ScanSpool::flush() {
  std::size_t done = 0;
  while (done < buffer_.size()) {
    const ssize_t n = ::write(fd_, buffer_.data() + done, buffer_.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0)
      throw Error("cannot keep the scans that do not fit in memory on disk: " +
                      (n == 0 ? std::string("no space left") : reason()) + " (after " +
                      std::to_string((written_ + done) / 1000000) + " MB)",
                  directory_.string());
    done += static_cast<std::size_t>(n);
  }
  written_ += done;
  buffer_.clear();
}

void ScanSpool::forEachBlock(std::size_t block_bytes,
                             const std::function<void(std::vector<LaserScan>& block, std::size_t first)>& f) const {
  if (!buffer_.empty()) throw Error("scan spool read before it was flushed", directory_.string());
  std::vector<LaserScan> block;
  // The file is read in large pieces; `bytes[pos, end)` holds what is read and not yet decoded.
  std::vector<unsigned char> bytes;
  std::size_t pos = 0;
  std::uint64_t at = 0;  // file offset of bytes' end
  std::size_t first = 0, index = 0, in_block = 0;
  auto read = [&](void* into, std::size_t n) {
    if (n == 0) return;  // a scan without beams: its data() may be null
    if (bytes.size() - pos < n) {
      bytes.erase(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(pos));
      pos = 0;
      std::size_t have = bytes.size();
      const std::size_t want = std::max<std::size_t>(n, kWriteBuffer);
      const auto left = static_cast<std::size_t>(written_ - at);
      bytes.resize(have + std::min(want, left));
      while (have < n) {
        const ssize_t r = ::pread(fd_, bytes.data() + have, bytes.size() - have, static_cast<off_t>(at));
        if (r < 0 && errno == EINTR) continue;
        if (r <= 0)
          throw Error("cannot read back the scans kept on disk: " +
                          (r == 0 ? std::string("file shorter than written") : reason()),
                      directory_.string());
        have += static_cast<std::size_t>(r);
        at += static_cast<std::uint64_t>(r);
      }
      bytes.resize(have);
    }
    std::memcpy(into, bytes.data() + pos, n);
    pos += n;
  };
  while (index < count_) {
    RecordHead h;
    read(&h, sizeof h);
    LaserScan s;
    s.timestamp = h.timestamp;
    s.start_angle = h.start_angle;
    s.angular_step = h.angular_step;
    s.max_range = h.max_range;
    s.laser_pose.t = Vec2(h.laser[0], h.laser[1]);
    s.laser_pose.theta = h.laser[2];
    s.odom_pose.t = Vec2(h.odom[0], h.odom[1]);
    s.odom_pose.theta = h.odom[2];
    s.laser_id = h.laser_id;
    s.has_odom = h.has_odom != 0;
    s.has_laser_pose = h.has_laser_pose != 0;
    s.ranges.resize(h.beams);
    read(s.ranges.data(), h.beams * sizeof(float));
    in_block += s.memoryBytes();
    block.push_back(std::move(s));
    ++index;
    if (in_block >= block_bytes || index == count_) {
      f(block, first);
      first = index;
      block.clear();
      in_block = 0;
    }
  }
}

}  // namespace glassmap
