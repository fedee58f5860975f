// Laser logs of any supported kind (see log.hpp).
#include "glassmap/io/log.hpp"

#include "glassmap/io/ros2_bag.hpp"
#include "glassmap/io/ros2_log.hpp"

namespace glassmap {

bool isRos2Bag(const std::filesystem::path& path) { return ros2::isBag(path); }

LaserLog readLog(const std::filesystem::path& path, const LogReadOptions& options, LogReadNotes* notes) {
  if (isRos2Bag(path)) return readRos2Log(path, options, notes);
  if (notes) *notes = {};
  return readCarmenLog(path, options.carmen);
}

}  // namespace glassmap
