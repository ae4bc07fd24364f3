// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The `Robot` concept (issue 19, item 1): the kinematics that carries the sensor (Sec. 3.2). A model has a joint
/// vector q (radians for revolute joints, metres for prismatic ones) with limits, forward kinematics of the sensor
/// frame T_WS(q), inverse kinematics near a seed configuration, the collision geometry of its links in link frames
/// placed in the world for a given q, and the fixed hand-eye transform T_FS (flange → sensor, Eqs. 3.1–3.2):
/// T_WS = T_WF · T_FS (`sensor_from_flange`, driver/concepts.hpp). Models: `FreeFlyingSensor` (robot/free_flying.hpp,
/// every pose reachable, no links), `nbs::kdl::UrdfRobot` (adapters/kdl, a URDF arm through KDL) and
/// `GrippedRobot<Arm>` (gripped/gripped_robot.hpp: an arm holding the object, the fixed sensor seen from the object).
/// Frames and units: docs/architecture.md. Const members of every model may run concurrently.

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <concepts>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/core/types.hpp"
#include "nbs/robot/collision_mesh.hpp"

namespace nbs {

/// A joint configuration q, one entry per joint: radians (revolute) or metres (prismatic).
using JointVector = Eigen::VectorXd;

/// Joint limits lower ≤ q ≤ upper, per joint; ±infinity for an unlimited joint (continuous, free flying).
struct JointLimits {
  JointVector lower;
  JointVector upper;

  [[nodiscard]] Eigen::Index size() const { return lower.size(); }
  /// True if q has the right size, is finite and lies within the limits (+`tolerance`, the joint's unit).
  [[nodiscard]] bool contains(const JointVector& q, double tolerance = 0.0) const {
    return q.size() == lower.size() && q.allFinite() && (q.array() >= lower.array() - tolerance).all() &&
           (q.array() <= upper.array() + tolerance).all();
  }
  /// Throws InvalidArgument naming `what`, the joint index and the values unless the sizes agree and every
  /// lower ≤ upper with neither NaN.
  void validate(const std::string& what = "joint limits") const {
    detail::require(lower.size() == upper.size(), what, ": ", lower.size(), " lower but ", upper.size(), " upper");
    for (Eigen::Index i = 0; i < lower.size(); ++i)
      detail::require(!std::isnan(lower[i]) && !std::isnan(upper[i]) && lower[i] <= upper[i], what, ": joint ", i,
                      " has limits [", lower[i], ", ", upper[i], "] (NaN or inverted)");
  }
};

/// One collision shape of a link, in the link frame L: the shape's own frame G is `T_LG`.
/// box: full edge lengths `size` (x, y, z), centred at G. cylinder: `radius`, `length` along G's z, centred at G.
/// capsule: the cylinder plus hemispherical caps of `radius` (total length `length` + 2 `radius`). sphere:
/// `radius` at G. mesh: the file `mesh_path` (as written in the model) scaled by `size` per axis; `mesh` holds its
/// triangles in G with that scale already applied (loaded once by the model, shared by copies; closed meshes are
/// solids, open ones shells: robot/collision_mesh.hpp), or is null if the model did not load it (then
/// LinkCollisionChecker refuses the shape unless told to skip meshes). Metres.
struct LinkShape {
  enum class Kind { box, cylinder, capsule, sphere, mesh };
  Kind kind = Kind::box;
  Pose T_LG = Pose::Identity();
  Vec3 size = Vec3::Zero();
  double radius = 0.0;
  double length = 0.0;
  std::string mesh_path;
  std::shared_ptr<const CollisionMesh> mesh;  ///< mesh only: the loaded, scaled triangles in G (or null)
};

/// A link's collision shape placed in the world for one configuration: T_WG = T_WL · T_LG.
struct PlacedShape {
  std::string link;
  LinkShape shape;
  Pose T_WG = Pose::Identity();
};

/// A robot carrying the sensor. With `r` const, q a JointVector, T a Pose:
///  - `r.joint_count()`: the number of joints n (may be 0 only for a fixed sensor);
///  - `r.joint_limits()`: JointLimits of size n (validated when the model is made);
///  - `r.fk(q)`: the sensor pose T_WS (sensor → world); throws InvalidArgument for a q of the wrong size or not
///    finite; q outside the limits is still evaluated;
///  - `r.ik(T, seed)`: a q within the limits with fk(q) = T (the model states its tolerance), near `seed` when the
///    model has a choice, or nullopt when T is unreachable; throws InvalidArgument for a non-rigid T or a bad seed;
///    deterministic (same T, seed and settings give the same answer);
///  - `r.collision_shapes(q)`: every link's collision shapes in the world for q (empty for a model without links);
///  - `r.hand_eye()`: T_FS (flange → sensor).
template <class R>
concept Robot = requires(const R& r, const JointVector& q, const Pose& T) {
  { r.joint_count() } -> std::convertible_to<std::size_t>;
  { r.joint_limits() } -> std::convertible_to<JointLimits>;
  { r.fk(q) } -> std::same_as<Pose>;
  { r.ik(T, q) } -> std::same_as<std::optional<JointVector>>;
  { r.collision_shapes(q) } -> std::same_as<std::vector<PlacedShape>>;
  { r.hand_eye() } -> std::same_as<Pose>;
};

/// Throws InvalidArgument naming `name` unless q has `n` entries, all finite.
inline void validate_joint_vector(const JointVector& q, std::size_t n, const char* name = "joint vector") {
  detail::require(q.size() == static_cast<Eigen::Index>(n), name, " has ", q.size(), " entries, the robot has ", n,
                  " joints");
  validate_finite(q, name);
}

/// The angle in radians of the rotation between two poses' rotations, in [0, π].
[[nodiscard]] inline double rotation_angle_between(const Pose& a, const Pose& b) {
  const Mat3 d = a.linear().transpose() * b.linear();
  const Vec3 s(d(2, 1) - d(1, 2), d(0, 2) - d(2, 0), d(1, 0) - d(0, 1));  // 2 sin(angle) · axis
  return std::atan2(0.5 * s.norm(), std::clamp(0.5 * (d.trace() - 1.0), -1.0, 1.0));
}

/// True if `a` and `b` agree within `position_m` metres and `angle_rad` radians.
[[nodiscard]] inline bool poses_agree(const Pose& a, const Pose& b, double position_m, double angle_rad) {
  return (a.translation() - b.translation()).norm() <= position_m && rotation_angle_between(a, b) <= angle_rad;
}

}  // namespace nbs
