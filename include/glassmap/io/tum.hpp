#pragma once
/// TUM trajectory files: one pose per line, "timestamp x y z qx qy qz qw" (what evo reads).

#include <filesystem>
#include <vector>

#include "glassmap/core/laser_scan.hpp"

namespace glassmap {

/// Reads a TUM file; '#' lines and empty lines are skipped. The heading is the yaw of the
/// quaternion (z and roll/pitch are dropped). Throws Error naming file, line and field.
std::vector<StampedPose> readTum(const std::filesystem::path& path);

/// Writes poses as TUM lines with z = 0 and the quaternion of the heading, in the shortest exact
/// decimal form. Written atomically.
void writeTum(const std::filesystem::path& path, const std::vector<StampedPose>& poses);

}  // namespace glassmap
