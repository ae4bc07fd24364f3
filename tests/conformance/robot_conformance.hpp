// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Conformance harness for nbs::Robot (include/nbs/robot/robot.hpp). Checked contract, for random joint vectors q
// within the limits (an unlimited joint is drawn from [−unlimited_range, unlimited_range]):
//  - joint_limits() has joint_count() entries, none NaN or inverted; hand_eye() is rigid;
//  - fk(q) is a finite right-handed rigid transform and deterministic;
//  - ik(fk(q), seed near q) succeeds in at least `min_ik_success` of the cases, every solution lies within the limits
//    and fk(solution) = fk(q) within the tolerances; ik is deterministic;
//  - collision_shapes(q): named links, rigid finite placements T_WG = T_WL · T_LG, finite non-negative sizes;
//  - bad input (q or seed of the wrong size, NaN in q, a non-rigid target) throws InvalidArgument and afterwards
//    fk gives the same poses as before (nothing changed).
#include "nbs_catch.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "nbs/core/detail/random.hpp"
#include "nbs/robot/robot.hpp"

namespace nbs::conformance {

struct RobotCase {
  int samples = 50;
  double position_tol_m = 1e-4;      ///< 0.1 mm
  double angle_tol_rad = 1.745e-3;   ///< 0.1°
  double min_ik_success = 1.0;       ///< share of ik(fk(q)) that must succeed
  double seed_noise = 0.05;          ///< the ik seed is q + uniform(±seed_noise) per joint, clamped to the limits
  double unlimited_range = 1.0;      ///< draw range of an unlimited joint
  std::uint64_t seed = 1;
};

struct RobotConformanceReport {
  int ik_tried = 0;
  int ik_solved = 0;
};

/// q uniform within the limits (an unlimited side replaced by ±range).
[[nodiscard]] inline JointVector random_joints(const JointLimits& l, std::mt19937_64& rng, double range) {
  JointVector q(l.size());
  for (Eigen::Index j = 0; j < q.size(); ++j) {
    const double lo = std::max(l.lower[j], -range), hi = std::min(l.upper[j], range);
    q[j] = lo + (hi - lo) * nbs::detail::uniform01(rng);
  }
  return q;
}

template <class R>
RobotConformanceReport check_robot_conformance(const R& robot, const RobotCase& c = {}) {
  static_assert(Robot<R>);
  RobotConformanceReport rep;
  const auto n = static_cast<Eigen::Index>(robot.joint_count());
  const JointLimits limits = robot.joint_limits();
  REQUIRE(limits.lower.size() == n);
  REQUIRE(limits.upper.size() == n);
  REQUIRE_NOTHROW(limits.validate());
  REQUIRE(pose_problem(robot.hand_eye()).empty());

  std::mt19937_64 rng(c.seed);
  std::vector<JointVector> qs;
  std::vector<Pose> poses;
  for (int i = 0; i < c.samples; ++i) {
    const JointVector q = random_joints(limits, rng, c.unlimited_range);
    const Pose T = robot.fk(q);
    INFO("sample " << i << " q = " << q.transpose());
    REQUIRE(pose_problem(T).empty());
    REQUIRE(robot.fk(q).matrix() == T.matrix());
    qs.push_back(q);
    poses.push_back(T);

    JointVector seed = q;
    for (Eigen::Index j = 0; j < n; ++j)
      seed[j] = std::clamp(q[j] + c.seed_noise * (2.0 * nbs::detail::uniform01(rng) - 1.0), limits.lower[j],
                           limits.upper[j]);
    ++rep.ik_tried;
    const std::optional<JointVector> s = robot.ik(T, seed);
    if (s) {
      ++rep.ik_solved;
      REQUIRE(limits.contains(*s));
      const Pose back = robot.fk(*s);
      INFO("ik solution " << s->transpose() << "\nposition error " << (back.translation() - T.translation()).norm()
                          << " m, angle error " << rotation_angle_between(back, T) << " rad");
      REQUIRE(poses_agree(back, T, c.position_tol_m, c.angle_tol_rad));
      const std::optional<JointVector> again = robot.ik(T, seed);
      REQUIRE(again);
      REQUIRE(*again == *s);
    }

    for (const PlacedShape& p : robot.collision_shapes(q)) {
      INFO("link " << p.link);
      REQUIRE(!p.link.empty());
      REQUIRE(pose_problem(p.T_WG).empty());
      REQUIRE(pose_problem(p.shape.T_LG).empty());
      REQUIRE(p.shape.size.allFinite());
      REQUIRE((p.shape.size.array() >= 0.0).all());
      REQUIRE(std::isfinite(p.shape.radius));
      REQUIRE(p.shape.radius >= 0.0);
      REQUIRE(std::isfinite(p.shape.length));
      REQUIRE(p.shape.length >= 0.0);
    }
  }
  CHECK(rep.ik_solved >= c.min_ik_success * rep.ik_tried);

  // Bad input throws and changes nothing.
  const JointVector q0 = qs.front();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  JointVector too_long(n + 1);
  too_long.setZero();
  JointVector with_nan = q0;
  if (n > 0) with_nan[0] = nan;
  Pose not_rigid = poses.front();
  not_rigid.linear() *= 1.5;
  Pose nan_pose = poses.front();
  nan_pose.translation().x() = nan;
  REQUIRE_THROWS_AS(robot.fk(too_long), InvalidArgument);
  if (n > 0) REQUIRE_THROWS_AS(robot.fk(with_nan), InvalidArgument);
  REQUIRE_THROWS_AS(robot.ik(poses.front(), too_long), InvalidArgument);
  if (n > 0) REQUIRE_THROWS_AS(robot.ik(poses.front(), with_nan), InvalidArgument);
  REQUIRE_THROWS_AS(robot.ik(not_rigid, q0), InvalidArgument);
  REQUIRE_THROWS_AS(robot.ik(nan_pose, q0), InvalidArgument);
  REQUIRE_THROWS_AS(robot.collision_shapes(too_long), InvalidArgument);
  for (std::size_t i = 0; i < qs.size(); ++i) REQUIRE(robot.fk(qs[i]).matrix() == poses[i].matrix());
  return rep;
}

}  // namespace nbs::conformance
