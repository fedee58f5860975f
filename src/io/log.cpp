// Laser logs of any supported kind (see log.hpp).
#include "glassmap/io/log.hpp"

namespace glassmap {

LaserLog readLog(const std::filesystem::path& path, const LogReadOptions& options, LogReadNotes* /*notes*/) {
  return readCarmenLog(path, options.carmen);
}

}  // namespace glassmap
