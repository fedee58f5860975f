#pragma once
/// Localization of a whole log against a floorplan as one call: the sensor model built over the
/// map (by name: glass, glass-paper, beam, field), then Monte Carlo localization from the log's
/// odometry and ranges (never its laser poses).

#include <string>

#include "glassmap/core/laser_scan.hpp"
#include "glassmap/geometry/vector_map.hpp"
#include "glassmap/localize/localizer.hpp"
#include "glassmap/sensor/sensor_model.hpp"

namespace glassmap::pipeline {

/// Everything localizeLog needs.
struct LocalizeOptions {
  std::string model = "glass";       ///< sensor model, one of sensor::sensorModelNames()
  sensor::SensorParams sensor;       ///< max_range is taken from the log's first scan
  localize::LocalizeOptions filter;  ///< particles, beams, initial pose, seed
};

/// The filter's result and the model it ran with.
struct LocalizeResult {
  localize::LocalizeResult run;  ///< trajectory, per-scan spread, counts, times
  std::string model;             ///< model name as the model reports it
};

/// Localizes every scan of `log` against `map`. Throws Error for an empty map, a log with no
/// scans or no odometry, or an unknown model name.
LocalizeResult localizeLog(const LaserLog& log, const VectorMap& map, const LocalizeOptions& options = {});

}  // namespace glassmap::pipeline
