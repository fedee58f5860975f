// libFuzzer target: CARMEN log reader, plain text and gzip (sniffed from the content). A log that
// reads is written back and read again: the round trip must give the same records (no silent
// garbage in the writer or the reader).
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "fuzz_common.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/io/carmen.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = glassmap::fuzz::writeScratch("input.clf", data, size);
  glassmap::CarmenReadOptions options;
  options.require_scans = false;
  glassmap::LaserLog log;
  try {
    log = glassmap::readCarmenLog(path, options);
  } catch (const glassmap::Error&) {
    return 0;
  }
  const auto again_path = glassmap::fuzz::scratchDir() / "again.clf";
  try {
    glassmap::writeCarmenLog(again_path, log);
  } catch (const glassmap::Error&) {
    return 0;  // e.g. a PARAM value the format cannot carry: refused with an Error, fine
  }
  const glassmap::LaserLog again = glassmap::readCarmenLog(again_path, options);  // must not throw
  if (again.scans.size() != log.scans.size() || again.odometry.size() != log.odometry.size() ||
      again.true_poses.size() != log.true_poses.size() || again.params != log.params)
    std::abort();
  for (std::size_t i = 0; i < log.scans.size(); ++i) {
    if (again.scans[i].ranges != log.scans[i].ranges || again.scans[i].timestamp != log.scans[i].timestamp)
      std::abort();
  }
  return 0;
}
