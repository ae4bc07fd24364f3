// SPDX-License-Identifier: BSD-3-Clause
// CollisionChecker conformance: NoCollisions, VoxelCollisionChecker over a hand-built obstacle space and over a
// ProbabilisticVoxelSpace, and a minimal user-written checker (the FCL checker: test_conformance_fcl).
#include "collision_checker_conformance.hpp"

#include <set>

#include "collision_spaces.hpp"

namespace {

using nbs::Aabb;
using nbs::Vec3;

/// The user-written checker: the head must stay above the floor z = 0 (lowest head corner).
struct FloorChecker {
  nbs::SensorHeadBox head;
  [[nodiscard]] bool collides(const nbs::Pose& T_WS) const {
    double lowest = std::numeric_limits<double>::infinity();
    for (const Vec3& c : nbs::test::corners(T_WS * head.center_m, T_WS.linear(), 0.5 * head.size_m))
      lowest = std::min(lowest, c.z());
    return lowest <= 0.0;
  }
};

}  // namespace

TEST_CASE("CollisionChecker conformance: NoCollisions and a user-written checker", "[conformance][collision]") {
  nbs::conformance::CollisionCase free_case;
  free_case.expect_both = false;
  nbs::conformance::check_collision_checker_conformance(nbs::NoCollisions{}, free_case);

  nbs::conformance::CollisionCase floor;
  floor.obstacles.push_back(Aabb{Vec3(-10, -10, -10), Vec3(10, 10, 0)});
  floor.lo = Vec3(-0.1, -0.1, -0.05);
  floor.hi = Vec3(0.1, 0.1, 0.15);
  nbs::conformance::check_collision_checker_conformance(FloorChecker{floor.head}, floor);
}

TEST_CASE("CollisionChecker conformance: VoxelCollisionChecker", "[conformance][collision]") {
  nbs::CollisionSetting cs;
  cs.head.size_m = Vec3(0.05, 0.03, 0.08);
  cs.static_scene.push_back(Aabb{Vec3(-1, -1, -0.3), Vec3(1, 1, -0.05)});            // table
  cs.static_scene.push_back(Aabb{Vec3(-0.03, -0.03, -0.05), Vec3(0.03, 0.03, 0.0)});  // pedestal
  cs.static_scene.push_back(Aabb{});                                                  // empty: ignored
  nbs::conformance::CollisionCase c;
  c.head = cs.head;
  c.lo = Vec3(-0.2, -0.2, -0.1);
  c.hi = Vec3(0.2, 0.2, 0.34);
  SECTION("hand-built obstacle voxels (a user's VoxelSpace)") {
    const nbs::conformance::HandBuiltObstacles space = nbs::conformance::HandBuiltObstacles::cross();
    c.obstacles = nbs::test::obstacle_boxes(space, cs);
    REQUIRE(c.obstacles.size() > 10);
    nbs::conformance::check_collision_checker_conformance(nbs::VoxelCollisionChecker(space, cs), c, 3);
  }
  SECTION("ProbabilisticVoxelSpace: occupied plate, free column, unknown rest of the bounds") {
    const auto space = nbs::conformance::plate_space();
    c.obstacles = nbs::test::obstacle_boxes(space, cs);
    REQUIRE(c.obstacles.size() > 10);
    nbs::conformance::check_collision_checker_conformance(nbs::VoxelCollisionChecker(space, cs), c, 4);
  }
}
