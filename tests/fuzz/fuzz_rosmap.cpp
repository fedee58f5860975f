// libFuzzer target: ROS map_server YAML + PGM reader. The input is split at the first
// "\n---PGM---\n" marker: the part before is map.yaml, the part after is the image map.pgm (when
// there is no marker, the whole input is the YAML and the image is a fixed tiny valid PGM).
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string_view>

#include "fuzz_common.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/io/ros_map.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static constexpr std::string_view kMarker = "\n---PGM---\n";
  static constexpr std::uint8_t kTinyPgm[] = {'P', '5', '\n', '2', ' ', '1', '\n', '2', '5', '5', '\n', 0, 254};
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  const std::size_t cut = input.find(kMarker);
  std::size_t yaml_size = size;
  if (cut != std::string_view::npos) {
    yaml_size = cut;
    const std::size_t img = cut + kMarker.size();
    glassmap::fuzz::writeScratch("map.pgm", data + img, size - img);
  } else {
    glassmap::fuzz::writeScratch("map.pgm", kTinyPgm, sizeof kTinyPgm);
  }
  const auto yaml = glassmap::fuzz::writeScratch("map.yaml", data, yaml_size);
  try {
    (void)glassmap::readRosMap(yaml);
  } catch (const glassmap::Error&) {
  }
  return 0;
}
