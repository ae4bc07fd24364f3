// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// `GrippedRobot<Arm>`: an arm holding the object (Sec. 5.4, Eq. 5.1) presented as a `Robot` (robot/robot.hpp) in
/// the object frame O, so that `RobotReach<GrippedRobot<Arm>>` lets NbsPlanner keep only the object poses the arm
/// can take. Frames as gripped/gripped_object.hpp: B the arm's world (its base side; the fixed sensor at T_BS), O the
/// object frame = the planner's world.
///
/// The arm's own model carries the object frame: its "sensor" is O (hand_eye() = T_FO, flange → object), so
/// arm.fk(q) = T_BO(q). The adaptor's "sensor pose" is the fixed sensor seen from the object:
///   fk(q) = T_BO(q)⁻¹ · T_BS = T_OS,    ik(T_OS, seed) = arm.ik(T_BS · T_OS⁻¹, seed)  (Eq. 5.1, object_pose_for).
/// A linear scan path of the sensor in O is the object's inverse linear path in B (object_path_for): the reach check
/// (check_scan_path) samples T_OS every ≤ 10 mm, and each sample's IK target is exactly the Eq. 5.1 object pose on
/// that path, the object positions as far apart as the sensor's. Tolerance: an arm IK error of ε_p metres and ε_a
/// radians in T_BO gives ≤ ε_p + ε_a · ‖t_BS − t_BO‖ metres and ε_a radians in T_OS (the standoff is the lever).
///
/// joint_count, joint_limits: the arm's. hand_eye() = T_BS: in O the arm's base B is the moving "flange" (T_OB(q))
/// and the fixed sensor is rigidly mounted on it at T_BS, so fk(q) = T_OB(q) · hand_eye() as Eqs. 3.1–3.2 read.
/// collision_shapes(q): the arm's shapes mapped into O (T_OG = T_BO(q)⁻¹ · T_BG), except those of the `attached`
/// links — the hand and fingers fixed in O, inside or at the tool box, which the voxel space would otherwise report
/// as colliding with the unknown object (model them as GrippedSetup::fingers instead) — plus the fixed sensor's body
/// (`sensor_body`, shapes in B, link names as given) mapped into O the same way. Check them against the voxel space
/// in O with LinkCollisionSetting::check_table = false: the table z = 0 of O is the palm plane, not a table (the
/// real table in B is not modeled here). Not checked at all: the arm against the fixed sensor in B (both fixed in B,
/// so their mutual collision is a question of B, not of the voxel space in O). Thread-safety: const members may run
/// concurrently if the arm's may.

#include <algorithm>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/core/types.hpp"
#include "nbs/gripped/gripped_object.hpp"
#include "nbs/robot/robot.hpp"

namespace nbs {

template <Robot Arm>
class GrippedRobot {
public:
  /// `arm` with its sensor frame = the object frame O (hand_eye() = T_FO); `T_BS` the fixed sensor in the arm's
  /// world B; `attached` names of arm links fixed to the object (left out of collision_shapes); `sensor_body` the
  /// fixed sensor's (or its mount's) shapes in B (PlacedShape::T_WG read as T_BG). Throws InvalidArgument (naming
  /// the value) for a non-rigid T_BS, an attached name the arm has no collision shape for (at q = 0 clamped into
  /// the limits), or a sensor-body shape that is unnamed, not finite, an unloaded mesh or not rigidly placed.
  GrippedRobot(Arm arm, const Pose& T_BS, std::vector<std::string> attached = {},
               std::vector<PlacedShape> sensor_body = {})
      : arm_(std::move(arm)), T_BS_(T_BS), attached_(std::move(attached)), sensor_body_(std::move(sensor_body)) {
    validate_pose(T_BS_, "GrippedRobot fixed sensor pose T_BS");
    if (!attached_.empty()) {
      const std::vector<PlacedShape> shapes = arm_.collision_shapes(zero_in_limits(arm_.joint_limits()));
      for (const std::string& name : attached_)
        detail::require(std::any_of(shapes.begin(), shapes.end(), [&](const PlacedShape& s) { return s.link == name; }),
                        "GrippedRobot attached link '", name, "': the arm has no collision shape of that link");
    }
    for (const PlacedShape& s : sensor_body_) {
      detail::require(!s.link.empty(), "GrippedRobot sensor_body: a shape without a name");
      detail::validate_loaded_shape(s, "GrippedRobot sensor_body");
      validate_pose(s.T_WG, detail::concat("GrippedRobot sensor_body '", s.link, "' pose T_BG"));
    }
  }

  [[nodiscard]] std::size_t joint_count() const { return arm_.joint_count(); }
  [[nodiscard]] JointLimits joint_limits() const { return arm_.joint_limits(); }
  /// T_BS (see the file comment: B is the moving flange seen from O).
  [[nodiscard]] Pose hand_eye() const { return T_BS_; }
  [[nodiscard]] const Arm& arm() const { return arm_; }
  [[nodiscard]] const Pose& sensor_pose_in_base() const { return T_BS_; }
  [[nodiscard]] const std::vector<std::string>& attached_links() const { return attached_; }

  /// The object pose T_BO(q) = arm.fk(q); throws as arm.fk.
  [[nodiscard]] Pose object_pose(const JointVector& q) const { return arm_.fk(q); }
  /// T_OS(q) = T_BO(q)⁻¹ · T_BS; throws as arm.fk.
  [[nodiscard]] Pose fk(const JointVector& q) const { return sensor_pose_in_object(T_BS_, arm_.fk(q)); }
  /// arm.ik(T_BS · T_OS⁻¹, seed) (Eq. 5.1). Throws InvalidArgument for a non-rigid T_OS (nothing solved) or what
  /// arm.ik throws (a bad seed).
  [[nodiscard]] std::optional<JointVector> ik(const Pose& T_OS, const JointVector& seed) const {
    return arm_.ik(object_pose_for(T_BS_, T_OS), seed);
  }

  /// The arm's shapes except the attached links', then the sensor body, all in O for q; throws as arm.fk.
  [[nodiscard]] std::vector<PlacedShape> collision_shapes(const JointVector& q) const {
    const Pose T_OB = arm_.fk(q).inverse(Eigen::Isometry);
    std::vector<PlacedShape> out;
    for (PlacedShape& s : arm_.collision_shapes(q)) {
      if (std::find(attached_.begin(), attached_.end(), s.link) != attached_.end()) continue;
      s.T_WG = T_OB * s.T_WG;
      out.push_back(std::move(s));
    }
    for (PlacedShape s : sensor_body_) {
      s.T_WG = T_OB * s.T_WG;
      out.push_back(std::move(s));
    }
    return out;
  }

private:
  /// 0 clamped into each joint's limits.
  static JointVector zero_in_limits(const JointLimits& l) {
    JointVector q(l.size());
    for (Eigen::Index j = 0; j < q.size(); ++j) q[j] = std::clamp(0.0, l.lower[j], l.upper[j]);
    return q;
  }

  Arm arm_;
  Pose T_BS_;
  std::vector<std::string> attached_;
  std::vector<PlacedShape> sensor_body_;
};

}  // namespace nbs
