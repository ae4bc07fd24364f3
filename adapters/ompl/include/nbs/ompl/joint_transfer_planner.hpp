// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// nbs::ompl — transfer motions of a robot between two scans, planned in joint space (issue 19, item 3; Sec. 3.2.2:
/// RRT-Connect in the arm's configuration space against the voxel space, p > 0.05 obstacles, unknown included, then
/// smoothed). `plan_joint_transfer(robot, validity, q_start, q_goal, setting)`: an OMPL RealVectorStateSpace over
/// the robot's joints bounded by its limits, RRT-Connect, then OMPL's `PathSimplifier` (vertex reduction and
/// shortcutting by default, `JointSimplify::full` adds B-spline smoothing); every straight joint motion is checked at
/// configurations at most `check_resolution` apart. The scan paths themselves (a joint trajectory every ≤ 10 mm of
/// the sensor) are checked by `RobotPathChecker` (robot/link_collision.hpp), not here.
///
/// Validity: any `JointValidity` (`first_contact(q) -> std::optional<LinkContact>`). The default is
/// `nbs::LinkCollisionChecker(robot, space, setting)`: the link shapes against the space's voxels with p > 0.05
/// (unknown included) and the table. It reads the space on every check, so it is always current after a scan and
/// costs nothing to keep up to date; an FCL obstacle model (nbs::fcl) would have to be rebuilt from the space after
/// every integration (an OctoMap export of every voxel of the unknown area), and LinkCollisionChecker checks mesh
/// link shapes too (`LinkShape::mesh`, loaded by the robot model). So no FCL here. Cost: one LinkCollisionChecker
/// query per checked configuration (LWR: about 2 µs with no link near the voxels, up to about 1 ms with links inside
/// a box of 5 mm voxels; a mesh link costs O(triangles) per voxel near it; docs/robot.md).
///
/// Linking with nbs::kdl (Debian's OMPL 1.5.2 and KDL 1.5.1): link nbs::kdl before nbs::ompl, else KDL's IK runs
/// OMPL's exported copy of Eigen's JacobiSVD and aborts (docs/robot.md, "Transfer motions in joint space").
///
/// Reproducible: single-threaded; the state sampler, RRT-Connect's and the simplifier's generators are seeded from
/// `JointTransferSetting::seed`; RRT-Connect stops after `max_iterations` (never on time), so the same inputs give
/// the same path on any machine load. (OMPL's nearest-neighbour structure draws its pivots from OMPL's global
/// generator; that changes its layout, not the exact nearest neighbour it returns.)

#include <ompl/base/ScopedState.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/PathSimplifier.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "nbs/core/detail/random.hpp"
#include "nbs/core/error.hpp"
#include "nbs/robot/link_collision.hpp"
#include "nbs/robot/robot.hpp"
#include "nbs/robot/transfer.hpp"
#include "nbs/space/concepts.hpp"

namespace nbs::ompl {

/// A configuration check for the transfer planner: `v.first_contact(q)` is nullopt if q is valid, else the contact
/// that makes it invalid. `nbs::LinkCollisionChecker` models it. Called from the planning thread only.
template <class V>
concept JointValidity = requires(const V& v, const JointVector& q) {
  { v.first_contact(q) } -> std::convertible_to<std::optional<LinkContact>>;
};

/// What OMPL's `PathSimplifier` (seeded) does with RRT-Connect's path.
enum class JointSimplify {
  none,      ///< RRT-Connect's path as it is
  shortcut,  ///< `reduceVertices` then `shortcutPath`: waypoints dropped / joined by straight motions when those pass
  full       ///< `simplifyMax`: shortcutting, B-spline smoothing, vertex collapsing until nothing improves (slower)
};

/// Settings of plan_joint_transfer. Joint-space distances are Euclidean over q (radians for revolute joints, metres
/// for prismatic ones).
struct JointTransferSetting {
  /// Largest joint-space distance between two configurations checked along a straight joint motion (> 0); every
  /// joint then moves at most this much between checks. A point r metres from every axis of an n-joint arm moves at
  /// most r·√n·check_resolution between checks (0.01 rad, LWR n = 7, r = 1 m: 26 mm; usually far less).
  double check_resolution = 0.01;
  double range = 0.5;             ///< RRT-Connect's largest extension step, joint-space distance (> 0)
  unsigned max_iterations = 5000;  ///< RRT-Connect iterations before giving up (≥ 1)
  std::uint64_t seed = 1;          ///< seeds the sampler, RRT-Connect and the simplifier
  JointSimplify simplify = JointSimplify::shortcut;  ///< what OMPL's PathSimplifier does with the path found

  /// Throws InvalidArgument naming the first bad field.
  void validate() const {
    nbs::detail::require_positive("JointTransferSetting::check_resolution", check_resolution);
    nbs::detail::require_positive("JointTransferSetting::range", range);
    nbs::detail::require(max_iterations >= 1, "JointTransferSetting::max_iterations must be >= 1, got ",
                         max_iterations);
  }
};

/// Why a transfer was (not) planned.
enum class JointTransferStatus {
  ok,             ///< waypoints hold a valid motion
  start_invalid,  ///< q_start fails the validity check (`contact` says where)
  goal_invalid,   ///< q_goal fails the validity check (`contact` says where)
  no_path         ///< RRT-Connect found no motion within max_iterations
};

[[nodiscard]] inline std::string_view to_string(JointTransferStatus s) {
  switch (s) {
    case JointTransferStatus::ok: return "ok";
    case JointTransferStatus::start_invalid: return "start_invalid";
    case JointTransferStatus::goal_invalid: return "goal_invalid";
    case JointTransferStatus::no_path: return "no_path";
  }
  return "?";
}

/// The result of plan_joint_transfer.
struct JointTransfer {
  JointTransferStatus status = JointTransferStatus::no_path;
  std::string reason;                  ///< one line for people: the status, the colliding link, the budget
  std::optional<LinkContact> contact;  ///< start_invalid / goal_invalid: the first contact at that end
  /// ok: first = q_start, last = q_goal (exactly); straight joint motions between consecutive waypoints. Else empty.
  std::vector<JointVector> waypoints;
  double joint_length = 0.0;    ///< Σ Euclidean joint-space distance between waypoints (rad / m)
  double sensor_length_m = 0.0;  ///< the sensor origin's path length in the world (fk every check_resolution), m
  unsigned iterations = 0;       ///< RRT-Connect iterations used (0: the straight motion was free)

  [[nodiscard]] bool ok() const { return status == JointTransferStatus::ok; }
};

namespace detail {

/// OMPL's seed type from nbs's seed and a stream number (one per seeded generator).
[[nodiscard]] inline std::uint_fast32_t ompl_seed(std::uint64_t seed, std::uint64_t stream) {
  return static_cast<std::uint_fast32_t>(nbs::detail::splitmix64(seed ^ (0x9E3779B97F4A7C15ull * stream))) | 1u;
}

/// OMPL's uniform sampler over the joint box with an explicitly seeded generator (OMPL's default samplers take
/// their seeds from a process-wide generator, so they depend on how many generators the process made before).
class SeededJointSampler : public ::ompl::base::RealVectorStateSampler {
public:
  SeededJointSampler(const ::ompl::base::StateSpace* space, std::uint64_t seed) : RealVectorStateSampler(space) {
    rng_.setLocalSeed(ompl_seed(seed, 1));
  }
};

/// RRT-Connect with its own generator seeded.
class SeededRrtConnect : public ::ompl::geometric::RRTConnect {
public:
  SeededRrtConnect(const ::ompl::base::SpaceInformationPtr& si, std::uint64_t seed) : RRTConnect(si) {
    rng_.setLocalSeed(ompl_seed(seed, 2));
  }
};

/// OMPL's path simplifier with its generator seeded.
class SeededSimplifier : public ::ompl::geometric::PathSimplifier {
public:
  SeededSimplifier(const ::ompl::base::SpaceInformationPtr& si, std::uint64_t seed) : PathSimplifier(si) {
    rng_.setLocalSeed(ompl_seed(seed, 3));
  }
};

inline void to_state(const JointVector& q, ::ompl::base::State* s) {
  auto* v = s->as<::ompl::base::RealVectorStateSpace::StateType>()->values;
  for (Eigen::Index j = 0; j < q.size(); ++j) v[j] = q[j];
}

[[nodiscard]] inline JointVector to_joints(const ::ompl::base::State* s, Eigen::Index n) {
  const auto* v = s->as<::ompl::base::RealVectorStateSpace::StateType>()->values;
  return Eigen::Map<const JointVector>(v, n);
}

/// Throws InvalidArgument naming `name`, the joint and the value unless q has n finite entries within the limits.
inline void validate_in_limits(const JointVector& q, const JointLimits& lim, const char* name) {
  validate_joint_vector(q, static_cast<std::size_t>(lim.size()), name);
  for (Eigen::Index j = 0; j < q.size(); ++j)
    nbs::detail::require(q[j] >= lim.lower[j] && q[j] <= lim.upper[j], name, " joint ", j, " = ", q[j],
                         " is outside its limits [", lim.lower[j], ", ", lim.upper[j], "]");
}

[[nodiscard]] inline std::string describe(const char* which, const LinkContact& c) {
  std::ostringstream s;
  s << which << " configuration collides: link '" << c.link << "' with ";
  if (c.with == LinkContact::With::table)
    s << "the table";
  else
    s << "voxel (" << c.voxel.x << ", " << c.voxel.y << ", " << c.voxel.z << ")";
  return s.str();
}

}  // namespace detail

/// Plans a motion of `robot` from q_start to q_goal (joint space) on which every configuration checked — at most
/// `setting.check_resolution` apart along each straight joint motion, waypoints included — passes `validity`, and
/// every waypoint lies within the joint limits. If the straight motion q_start → q_goal passes, it is returned
/// without running RRT-Connect. Throws InvalidArgument for an invalid setting, a joint without finite limits
/// lower < upper (naming the joint), or a q_start / q_goal of the wrong size, not finite or outside the limits
/// (naming which, the joint and the value). Thread-safety: reentrant if `validity.first_contact` and the robot's
/// const members are; `robot` and `validity` are used only during the call.
template <Robot R, JointValidity V>
[[nodiscard]] JointTransfer plan_joint_transfer(const R& robot, const V& validity, const JointVector& q_start,
                                                const JointVector& q_goal, const JointTransferSetting& setting) {
  namespace ob = ::ompl::base;
  namespace og = ::ompl::geometric;
  setting.validate();
  const JointLimits lim = robot.joint_limits();
  const auto n = static_cast<Eigen::Index>(robot.joint_count());
  nbs::detail::require(n >= 1 && lim.size() == n, "plan_joint_transfer: the robot has ", n, " joints and ",
                       lim.size(), " limits");
  for (Eigen::Index j = 0; j < n; ++j)
    nbs::detail::require(std::isfinite(lim.lower[j]) && std::isfinite(lim.upper[j]) && lim.lower[j] < lim.upper[j],
                         "plan_joint_transfer needs finite joint limits with lower < upper: joint ", j, " has [",
                         lim.lower[j], ", ", lim.upper[j], "]");
  detail::validate_in_limits(q_start, lim, "plan_joint_transfer: q_start");
  detail::validate_in_limits(q_goal, lim, "plan_joint_transfer: q_goal");

  JointTransfer out;
  if (const std::optional<LinkContact> c = validity.first_contact(q_start)) {
    out.status = JointTransferStatus::start_invalid;
    out.contact = *c;
    out.reason = detail::describe("start", *c);
    return out;
  }
  if (const std::optional<LinkContact> c = validity.first_contact(q_goal)) {
    out.status = JointTransferStatus::goal_invalid;
    out.contact = *c;
    out.reason = detail::describe("goal", *c);
    return out;
  }

  auto space = std::make_shared<ob::RealVectorStateSpace>(static_cast<unsigned>(n));
  ob::RealVectorBounds bounds(static_cast<unsigned>(n));
  for (Eigen::Index j = 0; j < n; ++j) {
    bounds.setLow(static_cast<unsigned>(j), lim.lower[j]);
    bounds.setHigh(static_cast<unsigned>(j), lim.upper[j]);
  }
  space->setBounds(bounds);
  const std::uint64_t seed = setting.seed;
  space->setStateSamplerAllocator([seed](const ob::StateSpace* s) -> ob::StateSamplerPtr {
    return std::make_shared<detail::SeededJointSampler>(s, seed);
  });
  auto si = std::make_shared<ob::SpaceInformation>(space);
  si->setStateValidityChecker([&validity, n](const ob::State* s) {
    return !validity.first_contact(detail::to_joints(s, n)).has_value();
  });
  // OMPL's resolution is a fraction of the space's extent (the diagonal of the joint box, Euclidean).
  si->setStateValidityCheckingResolution(std::min(1.0, setting.check_resolution / space->getMaximumExtent()));
  si->setup();

  ob::ScopedState<ob::RealVectorStateSpace> start(space), goal(space);
  detail::to_state(q_start, start.get());
  detail::to_state(q_goal, goal.get());
  std::vector<JointVector> waypoints;
  if (si->checkMotion(start.get(), goal.get())) {
    waypoints = {q_start, q_goal};
  } else {
    auto pdef = std::make_shared<ob::ProblemDefinition>(si);
    pdef->setStartAndGoalStates(start, goal);
    detail::SeededRrtConnect planner(si, seed);
    planner.setRange(setting.range);
    planner.setProblemDefinition(pdef);
    planner.setup();
    unsigned iterations = 0;
    const ob::PlannerTerminationCondition ptc(
        [&iterations, &setting] { return ++iterations > setting.max_iterations; });
    const bool solved = planner.solve(ptc) == ob::PlannerStatus::EXACT_SOLUTION;
    out.iterations = std::min(iterations, setting.max_iterations);
    if (!solved) {
      out.status = JointTransferStatus::no_path;
      out.reason = "no path found within " + std::to_string(setting.max_iterations) + " RRT-Connect iterations";
      return out;
    }
    og::PathGeometric path(*pdef->getSolutionPath()->as<og::PathGeometric>());
    detail::SeededSimplifier simplifier(si, seed);
    if (setting.simplify == JointSimplify::shortcut) {
      simplifier.reduceVertices(path);
      simplifier.shortcutPath(path);
    } else if (setting.simplify == JointSimplify::full) {
      og::PathGeometric simplified(path);
      if (simplifier.simplifyMax(simplified)) path = simplified;  // false: invalid after simplifying; keep the raw
    }
    for (const ob::State* s : path.getStates()) waypoints.push_back(detail::to_joints(s, n));
    waypoints.front() = q_start;  // exact ends
    waypoints.back() = q_goal;
  }

  out.status = JointTransferStatus::ok;
  out.reason = "ok";
  out.waypoints = std::move(waypoints);
  const std::vector<JointVector>& w = out.waypoints;
  Vec3 prev = robot.fk(w.front()).translation();
  for (std::size_t i = 1; i < w.size(); ++i) {
    const double d = (w[i] - w[i - 1]).norm();
    out.joint_length += d;
    const int steps = std::max(1, static_cast<int>(std::ceil(d / setting.check_resolution)));
    for (int k = 1; k <= steps; ++k) {
      const Vec3 p = robot.fk(w[i - 1] + (w[i] - w[i - 1]) * (static_cast<double>(k) / steps)).translation();
      out.sensor_length_m += (p - prev).norm();
      prev = p;
    }
  }
  return out;
}

/// The OMPL model of nbs::TransferPlanner (robot/transfer.hpp) that the loop calls between scans (run_loop with a
/// transfer planner; issue 19, item 4): plan_joint_transfer with `LinkCollisionChecker(robot, space, links)` as
/// validity, built on every call, so the obstacles are the voxel space as it is at the call (p > 0.05 and unknown
/// voxels by default, as the thesis does; the table). A status other than ok becomes TransferPlan::failure (its
/// `reason`). Throws at construction what LinkCollisionSetting / JointTransferSetting validation throws; plan throws
/// what plan_joint_transfer throws (a q of the wrong size, not finite or outside the limits).
template <Robot R>
class JointTransferPlanner {
public:
  explicit JointTransferPlanner(R robot, LinkCollisionSetting links = {}, JointTransferSetting setting = {})
      : robot_(std::move(robot)), links_(std::move(links)), setting_(setting) {
    links_.validate();
    setting_.validate();
  }

  [[nodiscard]] std::size_t joint_count() const { return robot_.joint_count(); }
  [[nodiscard]] const R& robot() const { return robot_; }
  [[nodiscard]] const LinkCollisionSetting& links() const { return links_; }
  [[nodiscard]] const JointTransferSetting& setting() const { return setting_; }

  template <VoxelSpace Space>
  [[nodiscard]] TransferPlan plan(const JointVector& from, const JointVector& to, const Space& space) const {
    const LinkCollisionChecker<R, Space> validity(robot_, space, links_);
    JointTransfer t = plan_joint_transfer(robot_, validity, from, to, setting_);
    TransferPlan out;
    out.sensor_length_m = t.sensor_length_m;
    out.waypoints = std::move(t.waypoints);
    if (!t.ok()) out.failure = std::move(t.reason);
    return out;
  }

private:
  R robot_;
  LinkCollisionSetting links_;
  JointTransferSetting setting_;
};

}  // namespace nbs::ompl
