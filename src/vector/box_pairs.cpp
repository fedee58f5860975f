#include "box_pairs.hpp"

#include <CGAL/box_intersection_d.h>

#include <algorithm>

namespace glassmap::vector::detail {
namespace {

using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 2, std::size_t>;

Box toBox(const Eigen::AlignedBox2d& b, std::size_t i) {
  double lo[2] = {b.min().x(), b.min().y()}, hi[2] = {b.max().x(), b.max().y()};
  return Box(lo, hi, i);
}

}  // namespace

std::vector<std::pair<std::size_t, std::size_t>> overlappingPairs(const std::vector<Eigen::AlignedBox2d>& boxes) {
  std::vector<Box> b;
  b.reserve(boxes.size());
  for (std::size_t i = 0; i < boxes.size(); ++i)
    if (!boxes[i].isEmpty()) b.push_back(toBox(boxes[i], i));
  std::vector<std::pair<std::size_t, std::size_t>> out;
  CGAL::box_self_intersection_d(b.begin(), b.end(), [&](const Box& p, const Box& q) {
    out.emplace_back(std::min(p.info(), q.info()), std::max(p.info(), q.info()));
  });
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::pair<std::size_t, std::size_t>> pointsInBoxes(const std::vector<Eigen::Vector2d>& points,
                                                               const std::vector<Eigen::AlignedBox2d>& boxes) {
  std::vector<Box> p, b;
  p.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) p.push_back(toBox(Eigen::AlignedBox2d(points[i], points[i]), i));
  for (std::size_t i = 0; i < boxes.size(); ++i)
    if (!boxes[i].isEmpty()) b.push_back(toBox(boxes[i], i));
  std::vector<std::pair<std::size_t, std::size_t>> out;
  CGAL::box_intersection_d(p.begin(), p.end(), b.begin(), b.end(),
                           [&](const Box& point, const Box& box) { out.emplace_back(point.info(), box.info()); });
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace glassmap::vector::detail
