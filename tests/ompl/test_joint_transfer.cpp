// SPDX-License-Identifier: BSD-3-Clause
// nbs::ompl::plan_joint_transfer (issue 19, item 3) with the planar 3R arm (tests/robot/planar_robot.hpp) and
// LinkCollisionChecker over a small voxel space: around a wall of occupied voxels, every dense sample of the path
// re-checked by a brute-force oracle (the arm's capsules, computed here, against every wall voxel's cube);
// reproducibility, invalid ends, an enclosed goal, bad input.
#include "nbs_catch.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <ompl/util/Console.h>

#include "nbs/ompl/joint_transfer_planner.hpp"
#include "nbs/space/backend.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"
#include "robot/planar_robot.hpp"

using namespace nbs;
using nbs::ompl::JointTransferSetting;
using nbs::ompl::JointTransferStatus;
using nbs::ompl::plan_joint_transfer;
using nbs::test::PlanarArm;

namespace {

using Space = ProbabilisticVoxelSpace<>;
constexpr double kVoxel = 0.04;
constexpr double kLinkRadius = 0.02;  // PlanarArm's capsules

JointVector jv(double a, double b, double c) {
  JointVector q(3);
  q << a, b, c;
  return q;
}

/// The arm's plane y = 0 and around it, x and z within ±0.9 m of the base.
Space make_space() { return Space(kVoxel, Aabb{Vec3(-0.9, -0.03, -0.9), Vec3(0.9, 0.03, 0.9)}); }

/// Sets every voxel (all y layers) whose centre satisfies `inside` occupied; returns their cubes.
template <class F>
std::vector<Aabb> occupy(Space& space, F inside) {
  ThesisState occupied;
  occupied.surf = 6000;  // p ≈ 1
  std::vector<Aabb> cubes;
  const KeyBox b = space.bounds_keys();
  for (int z = b.min.z; z <= b.max.z; ++z)
    for (int y = b.min.y; y <= b.max.y; ++y)
      for (int x = b.min.x; x <= b.max.x; ++x) {
        const VoxelKey k{x, y, z};
        const Vec3 c = space.grid().center(k);
        if (!inside(c)) continue;
        set_voxel_state(space.mutable_backend(), k, occupied);
        cubes.push_back(Aabb{c - Vec3::Constant(0.5 * kVoxel), c + Vec3::Constant(0.5 * kVoxel)});
      }
  return cubes;
}

/// Only the voxels the test set count (unknown space is free here), no table: the arm hangs below z = 0 freely.
LinkCollisionSetting observed_only() {
  LinkCollisionSetting s;
  s.unknown_is_obstacle = false;
  s.check_table = false;
  return s;
}

/// A wall of the voxels with centres |x| < 0.03, z > 0.5 (cubes x ∈ [−0.04, 0.04], z ≥ 0.52): above the base, higher
/// than the folded arm, lower than the stretched one, so the arm must fold to pass from leaning left to leaning right.
bool in_wall(const Vec3& c) { return std::abs(c.x()) < 0.03 && c.z() > 0.5; }

/// The oracle: the arm's three capsules at q (joint positions computed here, PlanarArm's convention) touch a cube.
/// The distance from a point moving along the axis to a box is convex in the axis parameter: ternary search, exact
/// to 1e-9 of the link length.
bool oracle_collides(const PlanarArm& arm, const JointVector& q, const std::vector<Aabb>& cubes) {
  Vec3 p = Vec3::Zero();
  double phi = 0.0;
  for (int i = 0; i < 3; ++i) {
    phi += q[i];
    const Vec3 e = p + arm.l[static_cast<std::size_t>(i)] * Vec3(std::sin(phi), 0.0, std::cos(phi));
    for (const Aabb& b : cubes) {
      // No point of a cube farther than r + half its diagonal from the axis (centre to segment) can touch it.
      const Vec3 c = 0.5 * (b.min + b.max);
      const double tc = std::clamp((c - p).dot(e - p) / (e - p).squaredNorm(), 0.0, 1.0);
      if ((c - (p + tc * (e - p))).norm() > kLinkRadius + 0.5 * std::sqrt(3.0) * kVoxel + 1e-9) continue;
      const auto dist = [&](double t) {
        const Vec3 x = p + (e - p) * t;
        return (x - x.cwiseMax(b.min).cwiseMin(b.max)).norm();
      };
      double lo = 0.0, hi = 1.0;
      for (int it = 0; it < 60; ++it) {
        const double m1 = lo + (hi - lo) / 3.0, m2 = hi - (hi - lo) / 3.0;
        if (dist(m1) < dist(m2))
          hi = m2;
        else
          lo = m1;  // equal: the minimum lies between m1 and m2 (or both are minimal)
      }
      if (dist(0.5 * (lo + hi)) < kLinkRadius) return true;
    }
    p = e;
  }
  return false;
}

/// Every configuration along the straight joint motions, 1e-3 apart (10× denser than the planner's checks), is
/// free by the oracle and within the limits.
bool free_everywhere(const PlanarArm& arm, const std::vector<JointVector>& w, const std::vector<Aabb>& cubes) {
  for (std::size_t i = 1; i < w.size(); ++i) {
    const int n = std::max(1, static_cast<int>(std::ceil((w[i] - w[i - 1]).norm() / 1e-3)));
    for (int k = 0; k <= n; ++k) {
      const JointVector q = w[i - 1] + (w[i] - w[i - 1]) * (static_cast<double>(k) / n);
      if (!arm.limits.contains(q) || oracle_collides(arm, q, cubes)) return false;
    }
  }
  return true;
}

}  // namespace

TEST_CASE("joint transfer: the planar arm folds under a wall; dense brute-force re-check, exact ends, limits, "
          "lengths, same seed same path",
          "[ompl][joint]") {
  ::ompl::msg::setLogLevel(::ompl::msg::LOG_WARN);
  const PlanarArm arm;
  Space space = make_space();
  const std::vector<Aabb> wall = occupy(space, in_wall);
  REQUIRE(wall.size() >= 20);
  const LinkCollisionChecker links(arm, space, observed_only());
  const JointVector from = jv(-1.0, 0.3, 0.3), to = jv(1.0, 0.3, 0.3);
  REQUIRE_FALSE(oracle_collides(arm, from, wall));
  REQUIRE_FALSE(oracle_collides(arm, to, wall));
  REQUIRE(oracle_collides(arm, jv(0.0, 0.3, 0.3), wall));  // the straight motion crosses the wall

  const JointTransferSetting setting;
  const auto a = plan_joint_transfer(arm, links, from, to, setting);
  INFO(a.reason);
  REQUIRE(a.ok());
  CHECK(a.iterations > 0);
  REQUIRE(a.waypoints.size() >= 3);
  CHECK(a.waypoints.front() == from);
  CHECK(a.waypoints.back() == to);
  CHECK(free_everywhere(arm, a.waypoints, wall));
  double length = 0.0;
  for (std::size_t i = 1; i < a.waypoints.size(); ++i) length += (a.waypoints[i] - a.waypoints[i - 1]).norm();
  CHECK(a.joint_length == Approx(length));
  CHECK(a.joint_length > (to - from).norm());
  // The sensor's path is at least the chord between its end positions.
  CHECK(a.sensor_length_m >= (arm.fk(to).translation() - arm.fk(from).translation()).norm());

  JointTransferSetting other = setting;
  other.seed = 7;
  const auto c = plan_joint_transfer(arm, links, from, to, other);
  CHECK(c.ok());
  const auto b = plan_joint_transfer(arm, links, from, to, setting);  // after another seed's run: the same path
  REQUIRE(b.waypoints.size() == a.waypoints.size());
  for (std::size_t i = 0; i < a.waypoints.size(); ++i) CHECK(b.waypoints[i] == a.waypoints[i]);

  // A free straight motion is returned as it is, without RRT-Connect.
  const auto straight = plan_joint_transfer(arm, links, from, jv(-0.5, 0.3, 0.3), setting);
  REQUIRE(straight.ok());
  CHECK(straight.waypoints.size() == 2);
  CHECK(straight.iterations == 0);
  CHECK(straight.joint_length == Approx(0.5));
}

TEST_CASE("joint transfer: an end in collision names the end and the link; an enclosed goal has no path",
          "[ompl][joint]") {
  ::ompl::msg::setLogLevel(::ompl::msg::LOG_ERROR);
  const PlanarArm arm;
  Space space = make_space();
  const std::vector<Aabb> wall = occupy(space, in_wall);
  const LinkCollisionChecker links(arm, space, observed_only());
  const JointVector free_q = jv(-1.0, 0.3, 0.3), upright = jv(0.0, 0.0, 0.0);  // upright: link 2 in the wall

  const auto start = plan_joint_transfer(arm, links, upright, free_q, JointTransferSetting{});
  CHECK(start.status == JointTransferStatus::start_invalid);
  REQUIRE(start.contact);
  CHECK(start.contact->link == "link2");
  CHECK(start.reason.find("start") != std::string::npos);
  CHECK(start.reason.find("link2") != std::string::npos);
  CHECK(start.waypoints.empty());
  const auto goal = plan_joint_transfer(arm, links, free_q, upright, JointTransferSetting{});
  CHECK(goal.status == JointTransferStatus::goal_invalid);
  CHECK(goal.reason.find("goal") != std::string::npos);

  // Two posts at 0.2 m from the base at 1.0 and 2.0 rad from +z: link 1 (0.4 m) sweeps through one of them whenever
  // θ1 crosses 1.0 or 2.0, so a goal with θ1 = 1.5 cannot be reached from θ1 = 0 (θ1 is limited to [−π, π]).
  Space posts_space = make_space();
  const auto near_post = [](const Vec3& c) {
    for (double a : {1.0, 2.0})
      if (std::abs(c.x() - 0.2 * std::sin(a)) <= 0.5 * kVoxel && std::abs(c.z() - 0.2 * std::cos(a)) <= 0.5 * kVoxel)
        return true;
    return false;
  };
  (void)occupy(posts_space, near_post);
  const LinkCollisionChecker posts(arm, posts_space, observed_only());
  JointTransferSetting budget;
  budget.max_iterations = 300;
  const auto enclosed = plan_joint_transfer(arm, posts, jv(0.0, 0.0, 0.0), jv(1.5, 0.0, 0.0), budget);
  CHECK(enclosed.status == JointTransferStatus::no_path);
  CHECK(enclosed.reason.find("300") != std::string::npos);
  CHECK(enclosed.waypoints.empty());
  CHECK(enclosed.iterations == 300);
}

TEST_CASE("joint transfer: bad input throws naming the value", "[ompl][joint]") {
  const PlanarArm arm;
  const Space space = make_space();
  const LinkCollisionChecker links(arm, space, observed_only());
  const JointVector ok = jv(0.1, 0.2, 0.3);
  const auto throws_with = [&](const JointVector& a, const JointVector& b, const JointTransferSetting& s,
                               const std::string& text) {
    try {
      (void)plan_joint_transfer(arm, links, a, b, s);
    } catch (const InvalidArgument& e) {
      INFO(e.what());
      return std::string(e.what()).find(text) != std::string::npos;
    }
    return false;
  };
  CHECK(throws_with(JointVector::Zero(2), ok, {}, "q_start"));
  CHECK(throws_with(ok, jv(0.0, NAN, 0.0), {}, "q_goal"));
  CHECK(throws_with(ok, jv(0.0, 4.0, 0.0), {}, "q_goal joint 1 = 4"));
  JointTransferSetting bad;
  bad.check_resolution = 0.0;
  CHECK(throws_with(ok, ok, bad, "check_resolution"));
  bad = {};
  bad.max_iterations = 0;
  CHECK(throws_with(ok, ok, bad, "max_iterations"));
  PlanarArm unlimited;
  unlimited.limits.upper[2] = INFINITY;
  const LinkCollisionChecker unlimited_links(unlimited, space, observed_only());
  CHECK_THROWS_AS(plan_joint_transfer(unlimited, unlimited_links, ok, ok, {}), InvalidArgument);
}
