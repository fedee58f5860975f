// libFuzzer target: TUM trajectory reader.
#include <cstddef>
#include <cstdint>

#include "fuzz_common.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/io/tum.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = glassmap::fuzz::writeScratch("input.tum", data, size);
  try {
    (void)glassmap::readTum(path);
  } catch (const glassmap::Error&) {
  }
  return 0;
}
