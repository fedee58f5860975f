#include "glassmap/pipeline/localize_log.hpp"

#include "glassmap/core/error.hpp"
#include "local_frame.hpp"

namespace glassmap::pipeline {

LocalizeResult localizeLog(const LaserLog& log, const VectorMap& map, const LocalizeOptions& options) {
  if (map.segments.empty()) throw Error("the map has no segments", map.name);
  if (log.scans.empty()) throw Error("the log holds no scan to localize");
  sensor::SensorParams params = options.sensor;
  params.max_range = log.scans.front().max_range;
  // A plan in absolute coordinates is localized against in a frame re-centred on it (the same
  // estimates wherever its origin lies); the log's odometry enters only as motion between scans.
  Eigen::AlignedBox2d box;
  for (const MapSegment& s : map.segments) box.extend(s.a).extend(s.b);
  const Vec2 offset = detail::recentringOffset(box);
  VectorMap shifted;
  localize::LocalizeOptions filter = options.filter;
  if (!offset.isZero()) {
    shifted = map;
    for (MapSegment& s : shifted.segments) s.a -= offset, s.b -= offset;
    if (filter.init) filter.init->t -= offset;
  }
  const VectorMap& local = offset.isZero() ? map : shifted;
  const auto model = sensor::makeSensorModel(options.model, local, params);  // refitted when self-calibrating
  LocalizeResult out;
  out.model = model->name();
  out.run = localize::localizeLog(log, *model, filter);
  for (StampedPose& p : out.run.trajectory) p.pose.t += offset;
  return out;
}

}  // namespace glassmap::pipeline
