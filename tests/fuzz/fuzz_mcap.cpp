// libFuzzer target: MCAP reader of the ROS 2 bag storage (open, topics, every message in order).
#include <cstddef>
#include <cstdint>

#include "fuzz_common.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/io/ros2_bag.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = glassmap::fuzz::writeScratch("input.mcap", data, size);
  try {
    const auto bag = glassmap::ros2::openBag(path);
    std::uint64_t bytes = 0;
    bag->forEach({}, [&](const glassmap::ros2::BagMessage& m) {
      bytes += m.data.size() + m.topic->name.size();
      return true;
    });
    if (!bag->topics().empty()) {  // the filtered (chunk-skipping) path too
      bag->forEach({bag->topics().front().name}, [&](const glassmap::ros2::BagMessage& m) {
        bytes += m.data.size();
        return true;
      });
    }
    if (bytes == 0xFFFFFFFFFFFFFFFFull) std::abort();  // keeps the reads from being optimised away
  } catch (const glassmap::Error&) {
  }
  return 0;
}
