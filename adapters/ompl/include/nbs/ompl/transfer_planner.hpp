// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// nbs::ompl — collision-free transfer motions of the sensor between scan paths (Sec. 3.2.2: the thesis plans them
/// with RRT-Connect, smooths them and treats unknown and occupied voxels, p > 0.05, as obstacles). The sensor pose
/// T_WS is planned in SE(3) with OMPL's RRT-Connect; any `nbs::CollisionChecker` (e.g. `VoxelCollisionChecker` over
/// the planner's space, or `nbs::fcl::FclCollisionChecker`) decides validity. The robot's kinematics are not
/// modelled: a pose is reachable if its position lies in `TransferSetting::workspace` (the thesis's simulation
/// assumes an infinite workspace, Sec. 4.7).
///
/// Reproducible: RRT-Connect runs single-threaded with a state sampler seeded from `TransferSetting::seed` and stops
/// after `max_iterations` (not after a time), and the shortcutting is deterministic, so the same inputs and seed give
/// the same path on every machine load. Units: metres, radians, world frame.

#include <ompl/base/ScopedState.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/StateSampler.h>
#include <ompl/base/spaces/SE3StateSpace.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <vector>

#include "nbs/candidates/collision.hpp"
#include "nbs/core/error.hpp"
#include "nbs/core/types.hpp"

namespace nbs::ompl {

/// Settings of plan_transfer. Lengths in metres.
struct TransferSetting {
  Aabb workspace;                     ///< allowed sensor positions (world); must be a non-empty finite box.
  double check_resolution_m = 0.005;  ///< collision checks along a motion at most this far apart (position).
  double range_m = 0.05;              ///< RRT-Connect's step (translation part of OMPL's SE(3) distance).
  unsigned max_iterations = 20000;    ///< RRT-Connect iterations before giving up.
  std::uint64_t seed = 1;             ///< seed of the state sampler.
  bool shortcut = true;               ///< drop waypoints while the straight motion between the neighbours is free.

  /// Throws InvalidArgument naming the first bad field.
  void validate() const {
    nbs::detail::require(!workspace.empty() && workspace.min.allFinite() && workspace.max.allFinite(),
                    "TransferSetting.workspace must be a non-empty finite box");
    nbs::detail::require_positive("TransferSetting.check_resolution_m", check_resolution_m);
    nbs::detail::require_positive("TransferSetting.range_m", range_m);
    nbs::detail::require(max_iterations >= 1, "TransferSetting.max_iterations must be >= 1, got ", max_iterations);
  }
};

/// The result of plan_transfer. `solved` false: no collision-free motion within max_iterations (poses empty).
struct TransferPath {
  bool solved = false;
  std::vector<Pose> poses;  ///< T_WS waypoints, first = `from`, last = `to`; straight motions between them.
  double length_m = 0.0;    ///< summed translation along the waypoints.
};

namespace detail {

/// Uniform SE(3) sampler whose RNG is seeded explicitly (OMPL's default samplers draw their seeds from a global
/// generator, which depends on how many samplers the process made before).
class SeededSe3Sampler : public ::ompl::base::StateSampler {
public:
  SeededSe3Sampler(const ::ompl::base::StateSpace* space, const Aabb& box, std::uint64_t seed)
      : StateSampler(space), box_(box) {
    rng_.setLocalSeed(static_cast<std::uint_fast32_t>(seed ^ (seed >> 32)) | 1u);
  }
  void sampleUniform(::ompl::base::State* s) override {
    auto* st = s->as<::ompl::base::SE3StateSpace::StateType>();
    // One draw per statement, z first: the order gcc drew the former one-expression form (the order of draws
    // within one expression is unspecified; clang drew x first), so a seed gives the same states with any compiler.
    const double z = rng_.uniformReal(box_.min.z(), box_.max.z());
    const double y = rng_.uniformReal(box_.min.y(), box_.max.y());
    const double x = rng_.uniformReal(box_.min.x(), box_.max.x());
    st->setXYZ(x, y, z);
    double q[4];
    rng_.quaternion(q);
    auto& r = st->rotation();
    r.x = q[0];
    r.y = q[1];
    r.z = q[2];
    r.w = q[3];
  }
  void sampleUniformNear(::ompl::base::State* s, const ::ompl::base::State*, double) override { sampleUniform(s); }
  void sampleGaussian(::ompl::base::State* s, const ::ompl::base::State*, double) override { sampleUniform(s); }

private:
  Aabb box_;
};

inline void to_state(const Pose& p, ::ompl::base::SE3StateSpace::StateType* st) {
  st->setXYZ(p.translation().x(), p.translation().y(), p.translation().z());
  const Eigen::Quaterniond q(p.linear());
  auto& r = st->rotation();
  r.x = q.x();
  r.y = q.y();
  r.z = q.z();
  r.w = q.w();
}

inline Pose to_pose(const ::ompl::base::State* s) {
  const auto* st = s->as<::ompl::base::SE3StateSpace::StateType>();
  const auto& r = st->rotation();
  Pose p = Pose::Identity();
  p.linear() = Eigen::Quaterniond(r.w, r.x, r.y, r.z).normalized().toRotationMatrix();
  p.translation() = Vec3(st->getX(), st->getY(), st->getZ());
  return p;
}

}  // namespace detail

/// Plans a collision-free motion of the sensor from T_WS `from` to T_WS `to` (Sec. 3.2.2) with RRT-Connect; every
/// waypoint and every straight motion between two (checked every check_resolution_m of position, interpolating the
/// rotation) is collision-free under `checker` and inside the workspace. Throws InvalidArgument for an invalid
/// setting or a non-finite / non-rigid pose; returns `solved = false` if `from` or `to` collides or no motion was
/// found. Thread-safety: reentrant if `checker.collides` is.
template <CollisionChecker Checker>
[[nodiscard]] TransferPath plan_transfer(const Pose& from, const Pose& to, const Checker& checker,
                                         const TransferSetting& setting) {
  namespace ob = ::ompl::base;
  namespace og = ::ompl::geometric;
  setting.validate();
  validate_pose(from, "plan_transfer: from");
  validate_pose(to, "plan_transfer: to");

  auto space = std::make_shared<ob::SE3StateSpace>();
  ob::RealVectorBounds bounds(3);
  for (int a = 0; a < 3; ++a) {
    bounds.setLow(a, setting.workspace.min[a]);
    bounds.setHigh(a, setting.workspace.max[a]);
  }
  space->setBounds(bounds);
  const Aabb box = setting.workspace;
  const std::uint64_t seed = setting.seed;
  space->setStateSamplerAllocator([box, seed](const ob::StateSpace* s) -> ob::StateSamplerPtr {
    return std::make_shared<detail::SeededSe3Sampler>(s, box, seed);
  });
  auto si = std::make_shared<ob::SpaceInformation>(space);
  si->setStateValidityChecker([&checker, box](const ob::State* s) {
    const Pose p = detail::to_pose(s);
    return box.contains(p.translation()) && !checker.collides(p);
  });
  // OMPL's resolution is a fraction of the space's extent; the SE(3) extent mixes metres and radians, so the
  // fraction is taken of the workspace diagonal (the rotation part only adds checks).
  si->setStateValidityCheckingResolution(
      std::min(1.0, setting.check_resolution_m / std::max(space->getMaximumExtent(), 1e-9)));
  si->setup();

  TransferPath out;
  ob::ScopedState<ob::SE3StateSpace> start(space), goal(space);
  detail::to_state(from, start.get());
  detail::to_state(to, goal.get());
  if (!si->isValid(start.get()) || !si->isValid(goal.get())) return out;

  auto pdef = std::make_shared<ob::ProblemDefinition>(si);
  pdef->setStartAndGoalStates(start, goal);
  og::RRTConnect planner(si);
  planner.setRange(setting.range_m);
  planner.setProblemDefinition(pdef);
  planner.setup();
  unsigned iterations = 0;
  const ob::PlannerTerminationCondition ptc([&iterations, &setting] { return ++iterations > setting.max_iterations; });
  if (planner.solve(ptc) != ob::PlannerStatus::EXACT_SOLUTION) return out;

  auto* path = pdef->getSolutionPath()->as<og::PathGeometric>();
  std::vector<const ob::State*> states(path->getStates().begin(), path->getStates().end());
  if (setting.shortcut) {  // greedy: from each kept waypoint jump to the farthest one reachable in a straight motion
    std::vector<const ob::State*> kept{states.front()};
    for (std::size_t i = 0; i + 1 < states.size();) {
      std::size_t j = states.size() - 1;
      while (j > i + 1 && !si->checkMotion(states[i], states[j])) --j;
      kept.push_back(states[j]);
      i = j;
    }
    states = std::move(kept);
  }
  out.solved = true;
  for (const ob::State* s : states) out.poses.push_back(detail::to_pose(s));
  out.poses.front() = from;  // exact ends (the states hold them up to quaternion round trips)
  out.poses.back() = to;
  for (std::size_t i = 1; i < out.poses.size(); ++i)
    out.length_m += (out.poses[i].translation() - out.poses[i - 1].translation()).norm();
  return out;
}

}  // namespace nbs::ompl
