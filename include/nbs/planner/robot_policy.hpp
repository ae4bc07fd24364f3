// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The robot policy of NbsPlanner (issue 19, item 2): who carries the sensor. `FreeFlying` (default): every scan path
/// is executable, nothing is checked — today's plans. `RobotReach<R>`: a Robot R; Alg. 3 keeps a candidate only if R
/// can fly its linear scan path (`RobotPathChecker`: IK every ≤ 10 mm, continuous joints within limits, links vs the
/// voxel space and the table), with IK seeded from R's current configuration — the end of the last executed scan.

#include <cmath>
#include <concepts>
#include <optional>
#include <utility>

#include "nbs/core/error.hpp"
#include "nbs/core/scan_path.hpp"
#include "nbs/robot/link_collision.hpp"
#include "nbs/robot/reachability.hpp"
#include "nbs/robot/robot.hpp"
#include "nbs/space/concepts.hpp"

namespace nbs {

/// Default robot policy: a free-flying sensor (Sec. 4.7's infinite workspace). The planner checks nothing.
struct FreeFlying {
  [[nodiscard]] static constexpr bool active() { return false; }
};

/// Plan for the Robot R. Default-constructed: no robot, inactive (the planner then behaves as with FreeFlying).
/// Not thread-safe (the planner owns it); `check` is const and may run concurrently if R's const members may.
template <Robot R>
class RobotReach {
public:
  /// What an executable scan path is: the links' collision test (LinkCollisionSetting: p > 0.05 obstacles, unknown
  /// included, the table z = 0) and the path sampling / joint jump bound (ScanPathReachSetting: 10 mm, 0.2).
  struct Setting {
    LinkCollisionSetting links{};
    ScanPathReachSetting path{};
    /// λ of the transfer cost (issue 19 item 3), 1/rad, ≥ 0: the planner chooses the reachable candidate with the
    /// largest transfer_cost_score(u, d, λ) = u·exp(−λ·d) (u·exp(+λ·d) for u < 0), d = ‖q_start − q‖ the straight
    /// joint-space distance from the current configuration q to the candidate's first IK configuration (the reach
    /// check's, no motion planning). 0 (default): utility only, as the thesis chooses (its utility, Eq. 4.34, has no
    /// motion-cost term), and today's plans bit for bit.
    double transfer_cost_weight = 0.0;
    void validate() const {
      links.validate();
      path.validate();
      detail::require(std::isfinite(transfer_cost_weight) && transfer_cost_weight >= 0.0,
                      "RobotReach::Setting::transfer_cost_weight must be finite and >= 0 (1/rad), got ",
                      transfer_cost_weight);
    }
  };

  RobotReach() = default;
  /// Plans for `robot`, standing at `start` (the IK seed until the first scan is integrated). Throws InvalidArgument
  /// for a bad setting or a `start` of the wrong size, not finite or outside the joint limits.
  RobotReach(R robot, const JointVector& start, Setting setting = {})
      : robot_(std::move(robot)), setting_((setting.validate(), std::move(setting))) {
    set_configuration(start);
  }

  /// True if a robot is set (the planner checks reach).
  [[nodiscard]] bool active() const { return robot_.has_value(); }
  /// The robot; throws InvalidArgument if none is set.
  [[nodiscard]] const R& robot() const {
    detail::require(active(), "RobotReach::robot(): no robot set");
    return *robot_;
  }
  [[nodiscard]] const Setting& setting() const { return setting_; }
  /// The current joint configuration q (radians / metres): the IK seed of every reach check.
  [[nodiscard]] const JointVector& configuration() const { return q_; }
  /// Sets q; throws InvalidArgument (nothing changed) unless a robot is set and q is finite, of the robot's size and
  /// within its limits.
  void set_configuration(const JointVector& q) {
    validate_joint_vector(q, robot().joint_count(), "RobotReach configuration");
    detail::require(robot_->joint_limits().contains(q), "RobotReach configuration lies outside the joint limits");
    q_ = q;
  }

  /// Can the robot fly `path` from the current configuration, links checked against `space`? Throws as
  /// RobotPathChecker does. Requires active().
  template <VoxelSpace Space>
  [[nodiscard]] ScanPathReach check(const LinearScanPath& path, const Space& space) const {
    return RobotPathChecker<R, Space>(robot(), space, setting_.links, setting_.path).check(path, q_);
  }
  /// A checker for many paths against `space` (borrows the robot and the space); use with configuration().
  template <VoxelSpace Space>
  [[nodiscard]] RobotPathChecker<R, Space> checker(const Space& space) const {
    return RobotPathChecker<R, Space>(robot(), space, setting_.links, setting_.path);
  }

  /// The planner planned a path whose trajectory ends at `q_end`: the IK seed for the scan's end pose.
  void planned(const JointVector& q_end) { hint_ = q_end; }
  /// A scan ended at sensor pose T_WS (world): q ← ik(T_WS) seeded from the planned end (or q). Returns false and
  /// keeps q if T_WS is unreachable (e.g. a first scan the robot cannot fly).
  bool scanned(const Pose& T_WS) {
    const std::optional<JointVector> q = robot().ik(T_WS, hint_.value_or(q_));
    hint_.reset();
    if (!q) return false;
    q_ = *q;
    return true;
  }

private:
  std::optional<R> robot_;
  Setting setting_{};
  JointVector q_;
  std::optional<JointVector> hint_;
};

/// The transfer-cost score of a candidate of utility u whose start configuration is d (rad, ≥ 0) away in joint
/// space, for the weight λ (1/rad, ≥ 0): u·exp(−λ·d) for u ≥ 0, u·exp(λ·d) for u < 0 — never above u, decreasing in
/// d for either sign (the gain·exp(−λ·cost) form of receding-horizon NBV planners). λ = 0 gives u.
[[nodiscard]] inline double transfer_cost_score(double u, double d, double lambda) {
  return u * std::exp((u < 0.0 ? lambda : -lambda) * d);
}

/// A robot policy of NbsPlanner: FreeFlying, or active() / setting() / checker / configuration / planned / scanned as
/// RobotReach has them.
template <class P, class Space>
concept RobotPolicy = std::same_as<P, FreeFlying> ||
                      requires(P& p, const P& cp, const LinearScanPath& path, const Space& s, const Pose& T,
                               const JointVector& q) {
                        { cp.active() } -> std::convertible_to<bool>;
                        { cp.setting().transfer_cost_weight } -> std::convertible_to<double>;
                        { cp.checker(s).check(path, q) } -> std::same_as<ScanPathReach>;
                        { cp.configuration() } -> std::convertible_to<JointVector>;
                        p.planned(q);
                        { p.scanned(T) } -> std::convertible_to<bool>;
                      };

}  // namespace nbs
