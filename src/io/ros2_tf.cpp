// Planar transform tree over time (see ros2_tf.hpp).
#include "glassmap/io/ros2_tf.hpp"

#include <algorithm>
#include <cmath>

namespace glassmap::ros2 {

double quaternionYaw(const QuaternionMsg& q) {
  return std::atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z));
}

double quaternionTilt(const QuaternionMsg& q0) {
  const double n = std::sqrt(q0.x * q0.x + q0.y * q0.y + q0.z * q0.z + q0.w * q0.w);
  const QuaternionMsg q{q0.x / n, q0.y / n, q0.z / n, q0.w / n};
  const double roll = std::atan2(2.0 * (q.w * q.x + q.y * q.z), 1.0 - 2.0 * (q.x * q.x + q.y * q.y));
  const double pitch = std::asin(std::clamp(2.0 * (q.w * q.y - q.z * q.x), -1.0, 1.0));
  return std::max(std::abs(roll), std::abs(pitch));
}

QuaternionMsg yawQuaternion(double yaw) { return {0.0, 0.0, std::sin(0.5 * yaw), std::cos(0.5 * yaw)}; }

void TfBuffer::add(const std::string& parent, const std::string& child, double t, const Pose2& T_parent_child,
                   bool is_static) {
  Edge& e = edges_[child];
  if (!e.times.empty() && e.parent != parent) {
    ++reparented_;
    e = Edge{};
  }
  e.parent = parent;
  if (is_static || e.is_static) {
    // a static edge keeps one value; a dynamic sample never overrides a static edge's frame pair
    if (e.is_static && !is_static) return;
    e.is_static = true;
    e.times.assign(1, t);
    e.poses.assign(1, T_parent_child);
    return;
  }
  // bags are in log-time order, stamps nearly so: insert from the back
  auto it = std::upper_bound(e.times.begin(), e.times.end(), t);
  const auto k = it - e.times.begin();
  e.times.insert(it, t);
  e.poses.insert(e.poses.begin() + k, T_parent_child);
}

void TfBuffer::add(const TFMessageMsg& msg, bool is_static) {
  for (const TransformStampedMsg& m : msg.transforms) {
    const QuaternionMsg& q = m.rotation;
    const double n2 = q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w;
    if (!(n2 > 1e-12) || !std::isfinite(n2) || !std::isfinite(m.translation.x) || !std::isfinite(m.translation.y) ||
        m.child_frame_id.empty() || m.header.frame_id.empty()) {
      ++invalid_;
      continue;
    }
    const double tilt = quaternionTilt(q);
    max_tilt_ = std::max(max_tilt_, tilt);
    if (tilt > kTiltWarnRad) ++tilted_;
    add(m.header.frame_id, m.child_frame_id, m.header.stamp.seconds(),
        Pose2(m.translation.x, m.translation.y, quaternionYaw(q)), is_static);
  }
}

std::optional<Pose2> TfBuffer::edgeAt(const Edge& e, double t, double tol) const {
  if (e.is_static) return e.poses.front();
  if (e.times.empty() || t < e.times.front() - tol || t > e.times.back() + tol) return std::nullopt;
  if (t <= e.times.front()) return e.poses.front();
  if (t >= e.times.back()) return e.poses.back();
  const auto hi = static_cast<std::size_t>(std::lower_bound(e.times.begin(), e.times.end(), t) - e.times.begin());
  if (e.times[hi] == t) return e.poses[hi];
  const std::size_t lo = hi - 1;
  const double span = e.times[hi] - e.times[lo];
  return Pose2::interpolate(e.poses[lo], e.poses[hi], (t - e.times[lo]) / span);
}

std::vector<std::string> TfBuffer::ancestors(const std::string& frame) const {
  std::vector<std::string> chain{frame};
  for (auto it = edges_.find(frame); it != edges_.end(); it = edges_.find(it->second.parent)) {
    if (std::find(chain.begin(), chain.end(), it->second.parent) != chain.end()) break;  // a cycle
    chain.push_back(it->second.parent);
  }
  return chain;
}

std::optional<Pose2> TfBuffer::lookup(const std::string& target, const std::string& source, double t) const {
  return lookup(target, source, t, tolerance_s_);
}

std::optional<Pose2> TfBuffer::lookup(const std::string& target, const std::string& source, double t,
                                      double tol) const {
  if (target == source) return Pose2();
  const std::vector<std::string> up_s = ancestors(source), up_t = ancestors(target);
  // the first ancestor of source that is also an ancestor of target
  std::size_t is = 0, it = 0;
  bool found = false;
  for (; is < up_s.size() && !found; ++is) {
    const auto f = std::find(up_t.begin(), up_t.end(), up_s[is]);
    if (f != up_t.end()) {
      it = static_cast<std::size_t>(f - up_t.begin());
      found = true;
      break;
    }
  }
  if (!found) return std::nullopt;
  // T_common_source = T_common_a * ... * T_x_source, and likewise for target
  auto chainTo = [&](const std::vector<std::string>& up, std::size_t n) -> std::optional<Pose2> {
    Pose2 T;
    for (std::size_t k = 0; k < n; ++k) {
      const auto p = edgeAt(edges_.at(up[k]), t, tol);
      if (!p) return std::nullopt;
      T = *p * T;
    }
    return T;
  };
  const auto T_common_source = chainTo(up_s, is);
  const auto T_common_target = chainTo(up_t, it);
  if (!T_common_source || !T_common_target) return std::nullopt;
  return T_common_target->inverse() * *T_common_source;
}

bool TfBuffer::connected(const std::string& target, const std::string& source) const {
  if (target == source) return true;
  const std::vector<std::string> up_s = ancestors(source), up_t = ancestors(target);
  for (const auto& f : up_s)
    if (std::find(up_t.begin(), up_t.end(), f) != up_t.end()) return true;
  return false;
}

bool TfBuffer::hasEdge(const std::string& parent, const std::string& child) const {
  const auto it = edges_.find(child);
  return it != edges_.end() && it->second.parent == parent;
}

std::string TfBuffer::parentOf(const std::string& frame) const {
  const auto it = edges_.find(frame);
  return it == edges_.end() ? std::string() : it->second.parent;
}

std::vector<std::string> TfBuffer::dynamicChildren(const std::string& parent) const {
  std::vector<std::string> out;
  for (const auto& [child, e] : edges_)
    if (e.parent == parent && !e.is_static) out.push_back(child);
  return out;
}

std::vector<TfBuffer::EdgeInfo> TfBuffer::edges() const {
  std::vector<EdgeInfo> out;
  for (const auto& [child, e] : edges_)
    out.push_back({e.parent, child, e.is_static, e.times.size(), e.times.empty() ? 0.0 : e.times.front(),
                   e.times.empty() ? 0.0 : e.times.back()});
  return out;
}

}  // namespace glassmap::ros2
