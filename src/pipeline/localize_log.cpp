#include "glassmap/pipeline/localize_log.hpp"

#include "glassmap/core/error.hpp"

namespace glassmap::pipeline {

LocalizeResult localizeLog(const LaserLog& log, const VectorMap& map, const LocalizeOptions& options) {
  if (map.segments.empty()) throw Error("the map has no segments", map.name);
  if (log.scans.empty()) throw Error("the log holds no scan to localize");
  sensor::SensorParams params = options.sensor;
  params.max_range = log.scans.front().max_range;
  const auto model = sensor::makeSensorModel(options.model, map, params);  // refitted when self-calibrating
  LocalizeResult out;
  out.model = model->name();
  out.run = localize::localizeLog(log, *model, options.filter);
  return out;
}

}  // namespace glassmap::pipeline
