// SPDX-License-Identifier: BSD-3-Clause
// FCL collision checker (adapters/fcl) against the core VoxelCollisionChecker and the corner-projection box oracle.
#include "nbs_catch.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "box_oracle.hpp"
#include "conformance/collision_spaces.hpp"
#include "nbs/fcl/collision_checker.hpp"

namespace {
using nbs::Aabb;
using nbs::Pose;
using nbs::Vec3;
using Space = nbs::ProbabilisticVoxelSpace<>;

using nbs::conformance::plate_space;

Pose random_pose(std::mt19937_64& rng) {
  return nbs::test::random_pose(rng, Vec3(-0.2, -0.2, -0.1), Vec3(0.2, 0.2, 0.34));
}
}  // namespace

TEST_CASE("FCL checker agrees with the core checker and the box oracle on random poses", "[fcl]") {
  const Space space = plate_space();
  nbs::CollisionSetting cs;
  cs.head.size_m = Vec3(0.05, 0.03, 0.08);
  cs.static_scene.push_back(Aabb{Vec3(-1, -1, -0.3), Vec3(1, 1, -0.05)});   // table
  cs.static_scene.push_back(Aabb{Vec3(-0.03, -0.03, -0.05), Vec3(0.03, 0.03, 0.0)});  // pedestal
  const nbs::fcl::FclCollisionChecker fcl_checker(space, cs);
  const nbs::VoxelCollisionChecker core(space, cs);
  const auto obstacles = nbs::test::obstacle_boxes(space, cs);
  REQUIRE(obstacles.size() > 2);
  std::mt19937_64 rng(2024);
  int hits = 0, misses = 0, skipped = 0;
  for (int i = 0; i < 600; ++i) {
    const Pose p = random_pose(rng);
    const int o = nbs::test::oracle_collides(obstacles, cs.head, p, 1e-4);
    if (o < 0) {
      ++skipped;
      continue;
    }
    INFO("pose " << i << "\n" << p.matrix());
    REQUIRE(fcl_checker.collides(p) == (o == 1));
    REQUIRE(core.collides(p) == (o == 1));
    (o == 1 ? hits : misses) += 1;
  }
  CHECK(hits >= 50);
  CHECK(misses >= 50);
  CHECK(skipped <= 30);
}

TEST_CASE("FCL checker: swept paths and distance", "[fcl]") {
  const Space space = plate_space();
  nbs::CollisionSetting cs;
  cs.static_scene.push_back(Aabb{Vec3(-1, -1, -0.3), Vec3(1, 1, -0.05)});
  const nbs::fcl::FclCollisionChecker fcl_checker(space, cs);
  const nbs::VoxelCollisionChecker core(space, cs);
  std::mt19937_64 rng(7);
  for (int i = 0; i < 20; ++i) {
    const Pose a = random_pose(rng);
    const nbs::LinearScanPath path(nbs::Viewpoint(a), a.translation() + Vec3(0.0, 0.3, -0.1));
    CHECK(nbs::collision_free_fraction(fcl_checker, path) == nbs::collision_free_fraction(core, path));
  }
  // Distance of an axis-aligned head (s_z = −z) to the obstacles, oracle: min over obstacle AABBs of the
  // AABB–AABB gap (head spans S-box [−0.05, 0.05] × [−0.03, 0.03] × [−0.12, 0], i.e. world z ∈ [z_0, z_0 + 0.12]).
  const auto obstacles = nbs::test::obstacle_boxes(space, cs);
  Pose down = Pose::Identity();
  down.linear() = Eigen::AngleAxisd(std::numbers::pi, Vec3::UnitX()).toRotationMatrix();
  int colliding = 0;
  for (const Vec3& at : {Vec3(0.08, 0.05, 0.30), Vec3(0.0, 0.0, 0.25), Vec3(0.12, -0.1, 0.22), Vec3(0.1, 0.1, 0.15)}) {
    down.translation() = at;
    const Aabb head{at - Vec3(0.05, 0.03, 0.0), at + Vec3(0.05, 0.03, 0.12)};
    double expected = std::numeric_limits<double>::infinity();
    for (const Aabb& b : obstacles) {
      const Vec3 gap = (b.min - head.max).cwiseMax(head.min - b.max).cwiseMax(0.0);
      expected = std::min(expected, gap.norm());
    }
    INFO("head at " << at.transpose());
    CHECK(fcl_checker.collides(down) == (expected == 0.0));
    CHECK(fcl_checker.distance(down) == Approx(expected).margin(1e-6));
    colliding += expected == 0.0 ? 1 : 0;
  }
  CHECK(colliding >= 1);
  CHECK(colliding <= 3);
}

TEST_CASE("FCL checker: bad input", "[fcl]") {
  const Space space = plate_space();
  nbs::CollisionSetting cs;
  const nbs::fcl::FclCollisionChecker fcl_checker(space, cs);
  Pose nan_pose = Pose::Identity();
  nan_pose.linear()(1, 1) = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_AS((void)fcl_checker.collides(nan_pose), nbs::InvalidArgument);
  CHECK_THROWS_AS((void)fcl_checker.distance(nan_pose), nbs::InvalidArgument);
  cs.head.size_m = Vec3(-0.1, 0.1, 0.1);
  CHECK_THROWS_AS(nbs::fcl::FclCollisionChecker(space, cs), nbs::InvalidArgument);
  cs.head.size_m = Vec3(0.1, 0.1, 0.1);
  CHECK_THROWS_AS(nbs::fcl::FclCollisionChecker(space, cs, 10), nbs::InvalidArgument);  // bounds hold 8000 voxels
}
