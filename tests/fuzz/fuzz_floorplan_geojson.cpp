// libFuzzer target: floorplan reader through GDAL/OGR, input as a .geojson file.
#include <cstddef>
#include <cstdint>

#include <cpl_error.h>

#include "fuzz_common.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/io/floorplan.hpp"

extern "C" int LLVMFuzzerInitialize(int*, char***);
extern "C" int LLVMFuzzerInitialize(int*, char***) {
  CPLSetErrorHandler(CPLQuietErrorHandler);  // GDAL warnings on stderr would drown the fuzzer log
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = glassmap::fuzz::writeScratch("input.geojson", data, size);
  try {
    (void)glassmap::readFloorplan(path);
  } catch (const glassmap::Error&) {
  }
  return 0;
}
