// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A planar 3R arm written out by hand: the test oracle for the Robot concept and check_scan_path.
// All three joints turn about the world y axis; the base is at the world origin. With d(φ) = (sin φ, 0, cos φ):
//   joint 2 at l1 d(θ1), joint 3 at + l2 d(θ1+θ2), sensor at + l3 d(φ), φ = θ1+θ2+θ3, sensor rotation R_y(φ)
// (sensor +z along the last link). IK is closed form: wrist w = p − l3 d(φ), cos θ2 = (|w|² − l1² − l2²)/(2 l1 l2),
// both elbow branches, the one nearer the seed first. Reachable poses: y = 0, rotation about y, |w| ≤ l1 + l2.
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "nbs/robot/robot.hpp"

namespace nbs::test {

struct PlanarArm {
  std::array<double, 3> l{0.4, 0.3, 0.1};  ///< link lengths, metres
  JointLimits limits = default_limits();
  bool ik_ignores_limits = false;  ///< a deliberately faulty IK, to test that check_scan_path checks the limits

  static JointLimits default_limits() {
    JointLimits j;
    j.lower = JointVector::Constant(3, -std::numbers::pi);
    j.upper = JointVector::Constant(3, std::numbers::pi);
    return j;
  }
  static Mat3 rot_y(double a) { return Eigen::AngleAxisd(a, Vec3::UnitY()).toRotationMatrix(); }
  static Vec3 dir(double a) { return {std::sin(a), 0.0, std::cos(a)}; }

  [[nodiscard]] std::size_t joint_count() const { return 3; }
  [[nodiscard]] JointLimits joint_limits() const { return limits; }
  [[nodiscard]] Pose hand_eye() const { return Pose::Identity(); }

  [[nodiscard]] Pose fk(const JointVector& q) const {
    validate_joint_vector(q, 3, "planar arm q");
    Pose T = Pose::Identity();
    T.translation() = l[0] * dir(q[0]) + l[1] * dir(q[0] + q[1]) + l[2] * dir(q[0] + q[1] + q[2]);
    T.linear() = rot_y(q[0] + q[1] + q[2]);
    return T;
  }

  [[nodiscard]] std::optional<JointVector> ik(const Pose& T, const JointVector& seed) const {
    validate_pose(T, "planar arm ik target");
    validate_joint_vector(seed, 3, "planar arm ik seed");
    const Mat3& R = T.linear();
    if (std::abs(T.translation().y()) > 1e-9 || (R.col(1) - Vec3::UnitY()).norm() > 1e-9) return std::nullopt;
    const double phi = std::atan2(R(0, 2), R(2, 2));
    const Vec3 w = T.translation() - l[2] * dir(phi);
    const double c = (w.squaredNorm() - l[0] * l[0] - l[1] * l[1]) / (2.0 * l[0] * l[1]);
    if (c > 1.0 + 1e-12 || c < -1.0 - 1e-12) return std::nullopt;
    const double alpha = std::atan2(w.x(), w.z());
    std::optional<JointVector> best;
    for (double sign : {1.0, -1.0}) {
      const double t2 = sign * std::acos(std::clamp(c, -1.0, 1.0));
      const double t1 = alpha - std::atan2(l[1] * std::sin(t2), l[0] + l[1] * std::cos(t2));
      JointVector q(3);
      q << t1, t2, phi - t1 - t2;
      for (int j = 0; j < 3; ++j) q[j] = nearest_turn(q[j], seed[j], j);
      if (!ik_ignores_limits && !limits.contains(q)) continue;
      if (!best || (q - seed).norm() < (*best - seed).norm()) best = q;
    }
    return best;
  }

  [[nodiscard]] std::vector<PlacedShape> collision_shapes(const JointVector& q) const {
    validate_joint_vector(q, 3, "planar arm q");
    std::vector<PlacedShape> out;
    Pose T = Pose::Identity();
    for (int i = 0; i < 3; ++i) {
      T.linear() = T.linear() * rot_y(q[i]);
      PlacedShape s;
      s.link = "link" + std::to_string(i + 1);
      s.shape.kind = LinkShape::Kind::capsule;
      s.shape.radius = 0.02;
      s.shape.length = l[static_cast<std::size_t>(i)];
      s.shape.T_LG.translation() = Vec3(0, 0, 0.5 * s.shape.length);
      s.T_WG = T * s.shape.T_LG;
      out.push_back(s);
      T.translation() += l[static_cast<std::size_t>(i)] * T.linear().col(2);
    }
    return out;
  }

private:
  // The angle a + 2πk nearest `seed` within joint j's limits (a itself if none is within).
  [[nodiscard]] double nearest_turn(double a, double seed, int j) const {
    const double two_pi = 2.0 * std::numbers::pi;
    double best = a;
    bool found = false;
    for (int k = -2; k <= 2; ++k) {
      const double v = a + k * two_pi;
      if (v < limits.lower[j] || v > limits.upper[j]) continue;
      if (!found || std::abs(v - seed) < std::abs(best - seed)) best = v;
      found = true;
    }
    return best;
  }
};

}  // namespace nbs::test
