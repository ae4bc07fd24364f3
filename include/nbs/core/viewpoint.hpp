// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Sensor viewpoint S = (s_x s_y s_z s_p; 0 0 0 1), Eq. (4.12).

#include "nbs/core/types.hpp"

namespace nbs {

/// A sensor viewpoint: the pose T_WS of the sensor frame in the world (Eq. 4.12).
/// s_z (third column) is the viewing direction; s_p is the optical centre in metres.
/// Invariant: the rotation is orthonormal and right-handed (checked on construction).
class Viewpoint {
public:
  /// Identity viewpoint at the world origin looking along +z.
  Viewpoint() : pose_(Pose::Identity()) {}

  /// Wraps a pose; throws InvalidArgument if it is not a finite rigid transform.
  explicit Viewpoint(const Pose& pose) : pose_(pose) { validate_pose(pose_, "viewpoint pose"); }

  /// Builds S from its columns (Eq. 4.12). Throws unless (s_x, s_y, s_z) is a right-handed orthonormal basis.
  static Viewpoint from_axes(const Vec3& s_x, const Vec3& s_y, const Vec3& s_z, const Vec3& s_p) {
    Pose p = Pose::Identity();
    p.linear().col(0) = s_x;
    p.linear().col(1) = s_y;
    p.linear().col(2) = s_z;
    p.translation() = s_p;
    return Viewpoint(p);
  }

  /// Viewpoint at `position` looking at `target`. The sensor x axis is chosen perpendicular to `up` where
  /// possible (s_x = s_z × up, normalised); `up` need not be orthogonal to the viewing direction.
  /// Throws if position == target or if `up` is parallel to the viewing direction.
  static Viewpoint look_at(const Vec3& position, const Vec3& target, const Vec3& up = Vec3::UnitZ()) {
    validate_finite(position, "look_at position");
    validate_finite(target, "look_at target");
    validate_finite(up, "look_at up");
    const Vec3 d = target - position;
    detail::require(d.norm() > 1e-12, "look_at: position equals target (", position.transpose(), ")");
    const Vec3 z = d.normalized();
    Vec3 x = z.cross(up);
    detail::require(x.norm() > 1e-9, "look_at: up (", up.transpose(), ") is parallel to the viewing direction");
    x.normalize();
    const Vec3 y = z.cross(x);
    return from_axes(x, y, z, position);
  }

  [[nodiscard]] const Pose& pose() const { return pose_; }
  [[nodiscard]] Vec3 x_axis() const { return pose_.linear().col(0); }
  [[nodiscard]] Vec3 y_axis() const { return pose_.linear().col(1); }
  /// Viewing direction s_z (unit, world frame).
  [[nodiscard]] Vec3 view_direction() const { return pose_.linear().col(2); }
  /// Optical centre s_p (world frame, metres).
  [[nodiscard]] Vec3 position() const { return pose_.translation(); }

private:
  Pose pose_;
};

}  // namespace nbs
