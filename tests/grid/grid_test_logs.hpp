#pragma once
/// Test helper of the grid tests: a laser looking along +x over +-20 deg (181 beams) at a wall at
/// x = 2 m, from (0, 0.1 s) in scan s; beam i of scan s reads nothing (max range 10 m) when
/// no_return(s, i).

#include <cmath>

#include "glassmap/core/angles.hpp"
#include "glassmap/core/laser_scan.hpp"

namespace glassmap::grid::test {

template <class NoReturn>
LaserLog wallLog(int scans, NoReturn no_return) {
  LaserLog log;
  for (int s = 0; s < scans; ++s) {
    LaserScan scan;
    scan.max_range = 10.0;
    scan.start_angle = deg2rad(-20.0);
    scan.angular_step = deg2rad(40.0 / 180.0);
    scan.laser_pose = Pose2(0.0, 0.1 * s, 0.0);
    for (int i = 0; i < 181; ++i)
      scan.ranges.push_back(no_return(s, i) ? 10.0f : static_cast<float>(2.0 / std::cos(scan.beamAngle(i))));
    log.scans.push_back(scan);
  }
  return log;
}

}  // namespace glassmap::grid::test
