#pragma once
/// The frame the pipeline computes in: logs and plans in absolute coordinates (UTM, a building's
/// survey grid: 10^5 to 10^7 m) are worked on in a frame re-centred on them, so that no result
/// depends on where the frame's origin lies (single-precision values and squared distances lose
/// centimetres out there). Data within 1 km of its origin stays where it is.

#include <Eigen/Geometry>

#include "glassmap/core/pose2.hpp"

namespace glassmap::pipeline::detail {

/// The offset to subtract from coordinates whose extent is `box`: zero when its centre lies within
/// 1 km of the origin, else the centre rounded to a multiple of 64 m (exact in binary, so shifting
/// there and back loses nothing of a grid's cell edges).
inline Vec2 recentringOffset(const Eigen::AlignedBox2d& box) {
  if (box.isEmpty()) return Vec2::Zero();
  const Vec2 centre = box.center();
  if (centre.cwiseAbs().maxCoeff() < 1000.0) return Vec2::Zero();
  return (centre / 64.0).array().round().matrix() * 64.0;
}

}  // namespace glassmap::pipeline::detail
