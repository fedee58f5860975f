#pragma once
/// A transform tree over time, as /tf and /tf_static carry it, projected onto the plane: each
/// transform's 3-D translation and quaternion become x, y and yaw (roll and pitch are dropped and
/// the largest seen is reported). Lookups compose the chain between two frames at a time,
/// interpolating each dynamic edge between its two neighbouring stamps (linear in translation,
/// shortest angle in yaw); static edges hold at every time.

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "glassmap/core/pose2.hpp"
#include "glassmap/io/ros2_cdr.hpp"

namespace glassmap::ros2 {

/// Roll and pitch of a unit quaternion [rad] (the tilt planar projection drops).
double quaternionTilt(const QuaternionMsg& q);
/// Yaw of a quaternion [rad] (normalised first).
double quaternionYaw(const QuaternionMsg& q);
/// Quaternion of a rotation about z by `yaw` [rad].
QuaternionMsg yawQuaternion(double yaw);

/// Roll or pitch beyond which a transform counts as tilted (the planar projection is then rough) [rad].
inline constexpr double kTiltWarnRad = 0.0872664626;  // 5 deg

/// Time-stamped planar transforms between named frames; a frame has at most one parent.
class TfBuffer {
 public:
  /// `tolerance_s`: how far beyond its first or last stamp an edge is still used (held) [s].
  explicit TfBuffer(double tolerance_s = 0.1) : tolerance_s_(tolerance_s) {}

  /// Adds T_parent_child at time t [s]. A static edge holds at every time (its latest value wins).
  /// A child given a new parent keeps the newest parent (counted in reparented()).
  void add(const std::string& parent, const std::string& child, double t, const Pose2& T_parent_child, bool is_static);
  /// Adds every transform of a TFMessage (header stamp, projected); degenerate quaternions are
  /// skipped and counted in invalid().
  void add(const TFMessageMsg& msg, bool is_static);

  /// T_target_source at time t: the chain through the tree, or nullopt when the frames are not
  /// connected or a dynamic edge on the chain has no sample within tolerance of t.
  std::optional<Pose2> lookup(const std::string& target, const std::string& source, double t) const;
  /// Same with another tolerance for this lookup [s].
  std::optional<Pose2> lookup(const std::string& target, const std::string& source, double t, double tolerance_s) const;
  /// True when target and source are connected (at some time).
  bool connected(const std::string& target, const std::string& source) const;
  /// True when `child` has `parent` as its direct parent.
  bool hasEdge(const std::string& parent, const std::string& child) const;
  /// The parent of `frame`, "" when it has none.
  std::string parentOf(const std::string& frame) const;
  /// The children of `parent` with a dynamic edge.
  std::vector<std::string> dynamicChildren(const std::string& parent) const;

  /// One edge of the tree, for reports.
  struct EdgeInfo {
    std::string parent, child;
    bool is_static = false;
    std::size_t samples = 0;
    double t_first = 0.0, t_last = 0.0;  ///< [s]
  };
  std::vector<EdgeInfo> edges() const;

  double maxTilt() const { return max_tilt_; }            ///< largest roll or pitch seen [rad]
  std::size_t tilted() const { return tilted_; }          ///< transforms tilted more than kTiltWarnRad
  std::size_t invalid() const { return invalid_; }        ///< transforms skipped (degenerate quaternion)
  std::size_t reparented() const { return reparented_; }  ///< transforms that moved a child to another parent
  double tolerance() const { return tolerance_s_; }       ///< [s]

 private:
  struct Edge {
    std::string parent;
    bool is_static = false;
    std::vector<double> times;  ///< sorted [s]
    std::vector<Pose2> poses;
  };
  std::optional<Pose2> edgeAt(const Edge& e, double t, double tolerance_s) const;
  /// Frames from `frame` up to the root (frame first).
  std::vector<std::string> ancestors(const std::string& frame) const;

  double tolerance_s_;
  std::map<std::string, Edge> edges_;  ///< by child frame
  std::size_t tilted_ = 0;
  double max_tilt_ = 0.0;
  std::size_t invalid_ = 0, reparented_ = 0;
};

}  // namespace glassmap::ros2
