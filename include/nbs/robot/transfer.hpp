// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Transfer motions between two scans (issue 19, items 3–4; Sec. 3.2.2): the arm moves in joint space from the
/// configuration at the end of one scan to the configuration at the start of the next, around the obstacles of the
/// voxel space as it is after the last scan. `TransferPlanner` is the customisation point the loop (run_loop with a
/// transfer planner, planner/simulation_loop.hpp) calls; `NoTransfer` models it for a free-flying sensor (nothing
/// to plan); the OMPL model (RRT-Connect in joint space + simplification) is `nbs::ompl::JointTransferPlanner`
/// (adapters/ompl/include/nbs/ompl/joint_transfer_planner.hpp). The core includes no adapter.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <concepts>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "nbs/robot/robot.hpp"
#include "nbs/space/concepts.hpp"

namespace nbs {

/// A planned transfer: a polyline in joint space, or a failure.
struct TransferPlan {
  /// ok(): first = the start configuration, last = the goal (exactly), straight joint motions between consecutive
  /// waypoints (radians / metres). Empty: no motion (NoTransfer) or a failure.
  std::vector<JointVector> waypoints;
  double sensor_length_m = 0.0;  ///< the sensor origin's path length along the motion (fk), metres; 0 for none
  std::string failure;           ///< empty: planned; else one line naming why not (e.g. the colliding link)

  [[nodiscard]] bool ok() const { return failure.empty(); }
};

/// Σ ‖q_{i+1} − q_i‖ (Euclidean over the joints) along `waypoints`: a transfer's joint-space length (rad for
/// revolute joints). 0 for fewer than two waypoints.
[[nodiscard]] inline double joint_path_length(const std::vector<JointVector>& waypoints) {
  double s = 0.0;
  for (std::size_t i = 1; i < waypoints.size(); ++i) s += (waypoints[i] - waypoints[i - 1]).norm();
  return s;
}

/// The most points sensor_path gives (a bound on the work and memory of one call).
inline constexpr double kMaxSensorPathPoints = 1e7;

/// The sensor origin's path in the world (metres) along the joint polyline `waypoints`: fk at the first waypoint,
/// then along each straight joint motion at steps whose largest joint change is ≤ `max_step` (rad / m), ending
/// exactly at each waypoint. For pictures of a transfer; Σ‖Δp‖ over it approaches TransferPlan::sensor_length_m.
/// Empty for no waypoints. Throws InvalidArgument (before any fk) for max_step ≤ 0 or not finite, a waypoint without
/// the robot's joint count or not finite, or a path of more than kMaxSensorPathPoints points; and what `robot.fk`
/// throws.
template <Robot R>
[[nodiscard]] std::vector<Vec3> sensor_path(const R& robot, const std::vector<JointVector>& waypoints,
                                            double max_step = 0.02) {
  detail::require(std::isfinite(max_step) && max_step > 0.0, "sensor_path: max_step must be finite and > 0, got ",
                  max_step);
  const auto n = static_cast<std::size_t>(robot.joint_count());
  std::vector<int> steps(waypoints.size(), 0);
  double points = waypoints.empty() ? 0.0 : 1.0;
  for (std::size_t i = 0; i < waypoints.size(); ++i) {
    validate_joint_vector(waypoints[i], n, detail::concat("sensor_path: waypoint ", i).c_str());
    if (i == 0) continue;
    const JointVector d = waypoints[i] - waypoints[i - 1];
    const double largest = d.size() ? d.cwiseAbs().maxCoeff() : 0.0;
    const double k = std::max(1.0, std::ceil(largest / max_step));
    points += k;
    detail::require(points <= kMaxSensorPathPoints, "sensor_path: max_step ", max_step, " gives more than ",
                    kMaxSensorPathPoints, " points (", k, " from waypoint ", i - 1, " to ", i, ")");
    steps[i] = static_cast<int>(k);
  }
  std::vector<Vec3> out;
  if (waypoints.empty()) return out;
  out.reserve(static_cast<std::size_t>(points));
  out.push_back(robot.fk(waypoints.front()).translation());
  for (std::size_t i = 1; i < waypoints.size(); ++i) {
    const JointVector d = waypoints[i] - waypoints[i - 1];
    for (int k = 1; k <= steps[i]; ++k)
      out.push_back(robot.fk(k == steps[i] ? waypoints[i] : JointVector(waypoints[i - 1] + d * (double(k) / steps[i])))
                        .translation());
  }
  return out;
}

/// A transfer planner for the voxel space type Space: `t.plan(from, to, space)` plans a motion from the joint
/// configuration `from` to `to` whose configurations are free against `space` as it is now (read during the call
/// only), or says why it cannot (`TransferPlan::failure`); it may throw InvalidArgument for a `from` / `to` of the
/// wrong size, not finite or outside the limits. `t.joint_count()`: the robot's n, 0 if the planner needs no joints
/// (NoTransfer).
template <class T, class Space>
concept TransferPlanner = VoxelSpace<Space> && requires(const T& t, const JointVector& q, const Space& space) {
  { t.plan(q, q, space) } -> std::same_as<TransferPlan>;
  { t.joint_count() } -> std::convertible_to<std::size_t>;
};

/// The free-flying sensor's transfer planner: nothing to plan (Sec. 4.7's infinite workspace). Every plan is ok,
/// without waypoints, of length 0.
struct NoTransfer {
  [[nodiscard]] static constexpr std::size_t joint_count() { return 0; }
  template <VoxelSpace Space>
  [[nodiscard]] TransferPlan plan(const JointVector&, const JointVector&, const Space&) const {
    return {};
  }
};

/// One executed transfer as the loop records it (ScanRecord::transfer).
struct TransferRecord {
  std::vector<JointVector> waypoints;  ///< TransferPlan::waypoints (empty: no motion, or failed)
  double joint_length_rad = 0.0;       ///< joint_path_length(waypoints): Σ ‖Δq‖, rad (m for prismatic joints)
  double sensor_length_m = 0.0;        ///< TransferPlan::sensor_length_m: the sensor's path in the world, m
  double t_plan_s = 0.0;               ///< wall time of motion planning, s: of the plan call (timed_transfer); of
                                       ///< every try of the step in transfer_with_retries (the loop)
  std::string failure;                 ///< TransferPlan::failure (empty: executed)
  /// Failed transfers of the same planning step (the loop: to other candidates, each then excluded) before this
  /// one; for a failed record all of them, this one included. 0: the first try succeeded.
  int failed_attempts = 0;

  [[nodiscard]] bool ok() const { return failure.empty(); }
};

/// `transfer.plan(from, to, space)`, timed, with its joint-space length. Throws what the planner throws.
template <class Transfer, VoxelSpace Space>
  requires TransferPlanner<Transfer, Space>
[[nodiscard]] TransferRecord timed_transfer(const Transfer& transfer, const JointVector& from, const JointVector& to,
                                            const Space& space) {
  const auto t0 = std::chrono::steady_clock::now();
  TransferPlan p = transfer.plan(from, to, space);
  TransferRecord r;
  r.t_plan_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.joint_length_rad = joint_path_length(p.waypoints);
  r.sensor_length_m = p.sensor_length_m;
  r.waypoints = std::move(p.waypoints);
  r.failure = std::move(p.failure);
  return r;
}

}  // namespace nbs
