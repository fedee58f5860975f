#pragma once
/// Checks made before localizing, shared by `glassmap localize` and the Python module: a plan
/// that is empty or of an implausible scale, an initial pose outside the plan.

#include <string>

#include "glassmap/core/pose2.hpp"
#include "glassmap/geometry/vector_map.hpp"

namespace glassmap::pipeline {

/// Throws Error (naming `plan_path`) when `map` has no segments, and when `scale_warning` (the
/// floorplan reader's implausible-extent warning, "" when plausible) is set and the caller did
/// not give the units explicitly: a plan of the wrong scale gives a confident wrong answer.
void checkLocalizationPlan(const VectorMap& map, const std::string& plan_path, const std::string& scale_warning,
                           bool units_given);

/// Throws Error (naming `plan_path`, field "init") when `init` lies outside the plan's extent
/// widened by 0.5 m + 5%: a start outside the plan is a wrong frame or wrong units.
void checkInitialPose(const VectorMap& map, const Pose2& init, const std::string& plan_path);

}  // namespace glassmap::pipeline
