#pragma once
/// How well a floorplan explains a log's own scans, for logs without ground truth: the share of
/// returns whose range the plan predicts within a tolerance, and the plan's size. A plan that
/// leaves out clutter explains fewer returns; one that draws clutter is larger: read both.
///
/// A return is explained when, walking its beam from the laser pose, the reading lies within
/// `tolerance` of a surface the beam meets before (or at) the first wall; glass is crossed (the
/// laser reads what lies behind most panes), so a reading at a pane or at anything the pane lets
/// through counts. The others are split by what the plan says about them: "short" readings end in
/// space the plan holds empty (clutter, people, furniture, or a wall the plan misses), "through
/// wall" readings run more than `tolerance` beyond a wall (the plan or the pose is wrong there).
///
/// A second, looser reading counts a return as near the plan when its end point lies within
/// `tolerance` of any segment, whatever the beam crossed on its way (the reading others report:
/// it forgives a plan that draws a surface the beam would have met first).

#include <cstddef>

#include "glassmap/core/laser_scan.hpp"
#include "glassmap/geometry/vector_map.hpp"

namespace glassmap::eval {

/// What counts as a return and how close it must be.
struct ConsistencyOptions {
  double tolerance = 0.10;    ///< |reading - surface| at most this [m]
  double max_range = 8.0;     ///< returns up to this range are scored [m]
  double min_range = 0.05;    ///< returns below this are the sensor's dead zone, not scored [m]
  std::size_t max_scans = 0;  ///< scans used, spread evenly over the log; 0: all
};

/// The figures.
struct ConsistencyResult {
  std::size_t scans = 0;          ///< scans scored
  std::size_t returns = 0;        ///< returns scored
  std::size_t explained = 0;      ///< ... explained within the tolerance
  std::size_t at_glass = 0;       ///< ... of which at a glass segment
  std::size_t short_of_plan = 0;  ///< ending in space the plan holds empty
  std::size_t through_wall = 0;   ///< running more than the tolerance through a wall
  double explained_share = 0.0;   ///< explained / returns (0 when there are none)
  std::size_t near_segment = 0;   ///< returns whose end point lies within the tolerance of a segment
  double near_share = 0.0;        ///< near_segment / returns
  std::size_t segments = 0;       ///< segments of the plan
  std::size_t wall_segments = 0, glass_segments = 0;
  double wall_length = 0.0, glass_length = 0.0;  ///< [m]
  double tolerance = 0.0, max_range = 0.0;       ///< the options used
};

/// Scores every return of `log` (laser poses in the plan's frame) against `plan`. Parallel over
/// scans; the result does not depend on the thread count.
ConsistencyResult rayConsistency(const LaserLog& log, const VectorMap& plan, const ConsistencyOptions& options = {});

}  // namespace glassmap::eval
