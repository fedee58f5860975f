#pragma once
/// Scans kept on disk instead of in memory: logs larger than the memory budget.
///
/// A reader appends the scans in log order; the passes over the log read them back in order,
/// block by block (forEachScanBlock in laser_scan.hpp). The file is a temporary one, unlinked as
/// soon as it is made, so nothing stays on disk after the process ends, however it ends. Values go
/// through bit for bit: a pass over a spooled log sees the very scans a log in memory holds.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <vector>

#include "glassmap/core/laser_scan.hpp"

namespace glassmap {

/// The block size a spooled log is read back in, for a log spooled above `spool_above_bytes` in
/// memory: half of that, within 1-32 MB, so that the passes stay within the reader's limit [bytes].
inline std::size_t spoolBlockBytes(std::size_t spool_above_bytes) {
  return std::clamp<std::size_t>(spool_above_bytes / 2, std::size_t{1} << 20, std::size_t{32} << 20);
}

class ScanSpool final : public ScanStore {
 public:
  /// Makes the temporary file in `directory` (must exist). Throws Error naming the folder.
  explicit ScanSpool(const std::filesystem::path& directory);
  ~ScanSpool();
  ScanSpool(const ScanSpool&) = delete;
  ScanSpool& operator=(const ScanSpool&) = delete;

  /// Appends a scan. Throws Error naming the folder and the system's reason (a full disk).
  void append(const LaserScan& scan);
  /// Writes out what append buffered; call before reading. Throws Error as append.
  void flush();

  std::size_t size() const { return count_; }                      ///< scans appended
  std::uint64_t bytesOnDisk() const override { return written_; }  ///< written so far (all after flush)
  const std::filesystem::path& directory() const { return directory_; }

  /// The scans in append order, block by block (ScanStore::forEachBlock). Needs flush().
  void forEachBlock(std::size_t block_bytes,
                    const std::function<void(std::vector<LaserScan>& block, std::size_t first)>& f) const override;

 private:
  std::filesystem::path directory_;
  int fd_ = -1;
  std::vector<unsigned char> buffer_;  // appended records not yet written
  std::uint64_t written_ = 0;
  std::size_t count_ = 0;
};

}  // namespace glassmap
