// libFuzzer target: floorplan reader through GDAL/OGR. Built twice (tests/fuzz/CMakeLists.txt):
// the input is written with the extension GLASSMAP_FUZZ_EXT (".dxf" or ".geojson"), which picks the
// driver and, for DXF, the pre-check.
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
  const auto path = glassmap::fuzz::writeScratch("input" GLASSMAP_FUZZ_EXT, data, size);
  try {
    (void)glassmap::readFloorplan(path);
  } catch (const glassmap::Error&) {
  }
  return 0;
}
