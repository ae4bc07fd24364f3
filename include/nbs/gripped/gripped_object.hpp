// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Gripped-object modeling (Sec. 5.4, Eq. 5.1): the sensor is fixed, the robot holds the object and moves it.
///
/// Frames (metres): **B** the robot base (the real world; the fixed sensor is at T_BS); **O** the object (tool)
/// frame, rigidly attached to the TCP: the planner's world frame W. The planner plans exactly as for a moving sensor,
/// sensor poses T_OS relative to the object; Eq. 5.1 maps each to the object pose the robot must take,
/// T_BO = T_BS · T_OS⁻¹ (the thesis's ᵀTᵂ = ᵀTˢ (ᵂTˢ)⁻¹ with its W := the TCP and its T := the robot base). The tool
/// box (the unknown area, Sec. 4.1) is an axis-aligned box in O; its bottom face z = tool_box.min.z is the hand
/// (palm) plane: the planner keeps sensor positions above it (its support-plane rule), as above the pedestal, and
/// the object side resting on it is the "bottom" of c_a. The fingers are known shapes in O (robot/robot.hpp
/// `PlacedShape`, `T_WG` read as T_OG); their points are removed from every scan before integration
/// (`remove_finger_points`) and do not count as object surface.

#include <algorithm>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "nbs/core/scan.hpp"
#include "nbs/core/scan_path.hpp"
#include "nbs/core/types.hpp"
#include "nbs/robot/link_collision.hpp"
#include "nbs/robot/robot.hpp"

namespace nbs {

/// A gripped-object set-up. Invariants (`validate`): T_BS rigid; tool_box finite with positive extent; every finger
/// shape finite with sizes ≥ 0 and a rigid pose; finger_margin_m finite and ≥ 0.
struct GrippedSetup {
  Pose T_BS = Pose::Identity();        ///< the fixed sensor in the robot base B (Eq. 5.1's ᵀTˢ)
  Aabb tool_box{Vec3::Zero(), Vec3::Zero()};  ///< the unknown area in O, metres (Sec. 5.4: 100 × 100 × 200 mm)
  std::vector<PlacedShape> fingers;    ///< the gripper's fingers in O (PlacedShape::T_WG is T_OG)
  /// A measured point within this distance of a finger (solid; shape_distance ≤ margin) is a finger point and is
  /// removed, metres. Cover the sensor noise: e.g. 3σ of the range noise plus the pose error.
  double finger_margin_m = 0.002;

  /// Throws InvalidArgument naming the field and value.
  void validate() const {
    validate_pose(T_BS, "GrippedSetup.T_BS");
    detail::require(tool_box.min.allFinite() && tool_box.max.allFinite() &&
                        (tool_box.max.array() > tool_box.min.array()).all(),
                    "GrippedSetup.tool_box must be finite with max > min on every axis, got min (",
                    tool_box.min.transpose(), ") max (", tool_box.max.transpose(), ")");
    detail::require_non_negative("GrippedSetup.finger_margin_m", finger_margin_m);
    for (const PlacedShape& f : fingers) {
      detail::validate_loaded_shape(f, "GrippedSetup finger");
      validate_pose(f.T_WG, detail::concat("GrippedSetup finger '", f.link, "' pose T_OG"));
    }
  }
};

/// Eq. 5.1: the object (tool) pose T_BO = T_BS · T_OS⁻¹ that puts the object at `T_OS` relative to the fixed sensor
/// `T_BS`. Throws InvalidArgument (naming the pose) unless both are finite and rigid.
[[nodiscard]] inline Pose object_pose_for(const Pose& T_BS, const Pose& T_OS) {
  validate_pose(T_BS, "object_pose_for: fixed sensor pose T_BS");
  validate_pose(T_OS, "object_pose_for: planned sensor pose T_OS");
  return T_BS * T_OS.inverse(Eigen::Isometry);
}

/// The inverse of Eq. 5.1, used to align the data: the sensor pose in O when the robot holds the object at T_BO,
/// T_OS = T_BO⁻¹ · T_BS. Throws InvalidArgument unless both are finite and rigid.
[[nodiscard]] inline Pose sensor_pose_in_object(const Pose& T_BS, const Pose& T_BO) {
  validate_pose(T_BS, "sensor_pose_in_object: fixed sensor pose T_BS");
  validate_pose(T_BO, "sensor_pose_in_object: object pose T_BO");
  return T_BO.inverse(Eigen::Isometry) * T_BS;
}

/// The object's motion for a planned linear scan path (sensor fixed in B): at every arc fraction t the object is at
/// object_pose_for(T_BS, path.pose_at(t)). The orientation stays fixed, R_BO = R_BS · Rᵀ, and the object moves on a
/// straight line by −R_BO · (s_p² − s_p¹): the inverse path, as long as the sensor path.
struct ObjectPath {
  Pose start = Pose::Identity();  ///< T_BO at the path's start (t = 0)
  Pose end = Pose::Identity();    ///< T_BO at its end (t = 1)
};

/// Eq. 5.1 at both ends of `path`. Throws as object_pose_for.
[[nodiscard]] inline ObjectPath object_path_for(const Pose& T_BS, const LinearScanPath& path) {
  return {object_pose_for(T_BS, path.pose_at(0.0)), object_pose_for(T_BS, path.pose_at(1.0))};
}

/// Maps a scan measured by the fixed sensor into O (Sec. 5.4: "the transformations in the acquired range images are
/// inverted"): `scan_B` in the base frame (profile poses T_BS, points in B), `T_BO_of_profile[k]` the object pose
/// while profile k was measured. Profile k becomes T_BO_k⁻¹ · T_BS_k, each point p becomes T_BO_k⁻¹ · p. Throws
/// InvalidArgument (nothing changed) if the scan is invalid, the counts differ or an object pose is not rigid.
[[nodiscard]] inline Scan scan_in_object_frame(const Scan& scan_B, const std::vector<Pose>& T_BO_of_profile) {
  scan_B.validate();
  detail::require(T_BO_of_profile.size() == scan_B.profile_poses.size(), "scan_in_object_frame: ",
                  T_BO_of_profile.size(), " object poses for ", scan_B.profile_poses.size(), " profiles");
  for (std::size_t k = 0; k < T_BO_of_profile.size(); ++k)
    validate_pose(T_BO_of_profile[k], detail::concat("scan_in_object_frame: object pose of profile ", k));
  Scan out = scan_B;
  std::vector<Pose> inv(T_BO_of_profile.size());
  for (std::size_t k = 0; k < inv.size(); ++k) {
    inv[k] = T_BO_of_profile[k].inverse(Eigen::Isometry);
    out.profile_poses[k] = inv[k] * scan_B.profile_poses[k];
  }
  for (std::size_t i = 0; i < out.points.size(); ++i) out.points[i] = inv[out.profile_of_point[i]] * scan_B.points[i];
  return out;
}

/// Throws InvalidArgument naming both sizes unless `object_bounds` (the object's extent in O, metres: a declared
/// maximum size placed in the grip, or a ground-truth mesh's bounds) lies inside `setup.tool_box` (Sec. 5.4: the box
/// must hold the whole object; an object larger than its box would be cut off). Also validates the set-up.
inline void require_object_in_tool_box(const GrippedSetup& setup, const Aabb& object_bounds) {
  setup.validate();
  detail::require(!object_bounds.empty() && object_bounds.min.allFinite() && object_bounds.max.allFinite(),
                  "gripped object bounds are empty or not finite: min (", object_bounds.min.transpose(), ") max (",
                  object_bounds.max.transpose(), ")");
  const Aabb& b = setup.tool_box;
  const Vec3 size = object_bounds.extent(), box = b.extent();
  detail::require((object_bounds.min.array() >= b.min.array()).all() &&
                      (object_bounds.max.array() <= b.max.array()).all(),
                  "gripped object larger than its tool box: object ", size.x(), " x ", size.y(), " x ", size.z(),
                  " m at [(", object_bounds.min.transpose(), "), (", object_bounds.max.transpose(), ")], tool box ",
                  box.x(), " x ", box.y(), " x ", box.z(), " m at [(", b.min.transpose(), "), (", b.max.transpose(),
                  ")]");
}

/// The distance from `p` (in O) to the nearest finger solid, metres (negative inside; +inf without fingers).
[[nodiscard]] inline double finger_distance(const std::vector<PlacedShape>& fingers, const Vec3& p) {
  double d = std::numeric_limits<double>::infinity();
  for (const PlacedShape& f : fingers) d = std::min(d, detail::shape_distance(f.shape, f.T_WG, p));
  return d;
}

/// Removes from `scan` (in O) every point with finger_distance ≤ setup.finger_margin_m, keeping the order of the
/// others (with their colours) and every profile pose; returns the number removed. The removed points are dropped entirely: they neither
/// add surface nor clear free space along their rays (the voxel space then learns a little less free space in front
/// of the fingers; the planner still sees the fingers' shadow as unknown). Throws InvalidArgument (nothing changed)
/// if the set-up or the scan is invalid. Cost: O(points × fingers).
inline std::size_t remove_finger_points(const GrippedSetup& setup, Scan& scan) {
  setup.validate();
  scan.validate();
  std::size_t kept = 0;
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    if (finger_distance(setup.fingers, scan.points[i]) <= setup.finger_margin_m) continue;
    scan.points[kept] = scan.points[i];
    scan.profile_of_point[kept] = scan.profile_of_point[i];
    if (scan.has_colors()) scan.colors[kept] = scan.colors[i];
    ++kept;
  }
  const std::size_t removed = scan.points.size() - kept;
  scan.points.resize(kept);
  scan.profile_of_point.resize(kept);
  if (scan.has_colors()) scan.colors.resize(kept);
  return removed;
}

}  // namespace nbs
