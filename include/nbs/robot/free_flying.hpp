// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// `FreeFlyingSensor`: the `Robot` that reproduces nbs's behaviour without a robot model — every sensor pose is
/// reachable, nothing collides (no links), the flange is the sensor (T_FS = I).

#include <Eigen/Geometry>

#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <vector>

#include "nbs/robot/robot.hpp"

namespace nbs {

/// The sensor flies freely: 6 joints q = (p_x, p_y, p_z, ω_x, ω_y, ω_z), the sensor position in metres (unlimited)
/// and the rotation vector ω (axis · angle, radians, each component in [−π, π], |ω| ≤ π) of T_WS's rotation.
/// fk is exact; ik is exact to rounding (≈1e-15) for every rigid pose and picks, at an angle of π, the rotation
/// vector nearer the seed. No links, T_FS = I. Stateless, thread-safe.
class FreeFlyingSensor {
public:
  [[nodiscard]] std::size_t joint_count() const { return 6; }

  [[nodiscard]] JointLimits joint_limits() const {
    constexpr double inf = std::numeric_limits<double>::infinity();
    constexpr double pi = std::numbers::pi;
    JointLimits l;
    l.lower.resize(6);
    l.upper.resize(6);
    l.lower << -inf, -inf, -inf, -pi, -pi, -pi;
    l.upper << inf, inf, inf, pi, pi, pi;
    return l;
  }

  /// T_WS of q; throws InvalidArgument for a q of the wrong size or not finite.
  [[nodiscard]] Pose fk(const JointVector& q) const {
    validate_joint_vector(q, 6, "free-flying joint vector");
    Pose T = Pose::Identity();
    const Vec3 w = q.tail<3>();
    const double angle = w.norm();
    if (angle > 0.0) T.linear() = Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
    T.translation() = q.head<3>();
    return T;
  }

  /// The joint vector of T_WS (always reachable); throws InvalidArgument for a non-rigid pose or a bad seed.
  [[nodiscard]] std::optional<JointVector> ik(const Pose& T_WS, const JointVector& seed) const {
    validate_pose(T_WS, "free-flying ik target");
    validate_joint_vector(seed, 6, "free-flying ik seed");
    const Eigen::AngleAxisd aa(T_WS.linear());
    Vec3 w = aa.angle() * aa.axis();
    // At angle π, ω and −ω are the same rotation: take the one nearer the seed.
    if (std::abs(aa.angle() - std::numbers::pi) < 1e-9 && (-w - seed.tail<3>()).norm() < (w - seed.tail<3>()).norm())
      w = -w;
    JointVector q(6);
    q << T_WS.translation(), w;
    return q;
  }

  [[nodiscard]] std::vector<PlacedShape> collision_shapes(const JointVector& q) const {
    validate_joint_vector(q, 6, "free-flying joint vector");
    return {};
  }

  [[nodiscard]] Pose hand_eye() const { return Pose::Identity(); }
};

}  // namespace nbs
