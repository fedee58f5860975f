#include "glassmap/pipeline/localize_checks.hpp"

#include <cstdio>

#include "glassmap/core/error.hpp"

namespace glassmap::pipeline {

void checkLocalizationPlan(const VectorMap& map, const std::string& plan_path, const std::string& scale_warning,
                           bool units_given) {
  if (map.segments.empty()) throw Error("the map has no segments", plan_path);
  if (!scale_warning.empty() && !units_given) throw Error("refusing to localize: " + scale_warning);
}

void checkInitialPose(const VectorMap& map, const Pose2& init, const std::string& plan_path) {
  Eigen::AlignedBox2d box = map.bounds();
  const double slack = 0.5 + 0.05 * (box.max() - box.min()).maxCoeff();
  box.extend(box.min() - Vec2::Constant(slack));
  box.extend(box.max() + Vec2::Constant(slack));
  if (box.contains(init.t)) return;
  char buf[200];
  std::snprintf(buf, sizeof buf, "(%.2f, %.2f) lies outside the map's extent x %.2f .. %.2f, y %.2f .. %.2f m",
                init.x(), init.y(), box.min().x() + slack, box.max().x() - slack, box.min().y() + slack,
                box.max().y() - slack);
  throw Error(std::string("the initial pose ") + buf + ": wrong units (see --units) or another frame?", plan_path, 0,
              "init");
}

}  // namespace glassmap::pipeline
