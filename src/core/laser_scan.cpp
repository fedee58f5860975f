// The max-range code of a log (see laser_scan.hpp).
#include "glassmap/core/laser_scan.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace glassmap {

bool markMaxRangeCode(LaserLog& log) {
  constexpr double kSlack = 0.005;  // readings within this of the code share it [m]
  struct Laser {
    double top = 0.0;
    std::size_t readings = 0, at_top = 0;
  };
  std::map<int, Laser> lasers;
  for (const LaserScan& s : log.scans) {
    Laser& l = lasers[s.laser_id];
    for (const float r : s.ranges) {
      if (!std::isfinite(r) || r <= 0.0f) continue;
      ++l.readings;
      l.top = std::max(l.top, static_cast<double>(r));
    }
  }
  for (const LaserScan& s : log.scans) {
    Laser& l = lasers[s.laser_id];
    for (const float r : s.ranges)
      if (std::isfinite(r) && r > 0.0f && static_cast<double>(r) >= l.top - kSlack) ++l.at_top;
  }
  bool found = false;
  for (auto& [id, l] : lasers) {
    const bool spike = l.top >= 1.0 && l.at_top >= 5 && static_cast<double>(l.at_top) >= 0.001 * static_cast<double>(l.readings);
    if (!spike) continue;
    found = true;
    // A code at or above the header's maximum is a max reading already: nothing to change.
    for (LaserScan& s : log.scans)
      if (s.laser_id == id && (s.max_range <= 0.0 || l.top < s.max_range)) s.max_range = l.top - kSlack;
    // The largest code when several lasers have one (info shows one figure).
    if (l.top > log.stats.max_range_code) {
      log.stats.max_range_code = l.top;
      log.stats.max_range_code_readings = l.at_top;
    }
  }
  return found;
}

}  // namespace glassmap
