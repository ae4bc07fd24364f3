// SPDX-License-Identifier: BSD-3-Clause
// CollisionChecker conformance for nbs::fcl::FclCollisionChecker (built only with the FCL adapter).
#include "collision_checker_conformance.hpp"
#include "collision_spaces.hpp"
#include "nbs/fcl/collision_checker.hpp"

TEST_CASE("CollisionChecker conformance: FclCollisionChecker", "[conformance][collision][fcl]") {
  nbs::CollisionSetting cs;
  cs.head.size_m = nbs::Vec3(0.05, 0.03, 0.08);
  cs.static_scene.push_back(nbs::Aabb{nbs::Vec3(-1, -1, -0.3), nbs::Vec3(1, 1, -0.05)});
  const auto space = nbs::conformance::plate_space();
  nbs::conformance::CollisionCase c;
  c.head = cs.head;
  c.lo = nbs::Vec3(-0.2, -0.2, -0.1);
  c.hi = nbs::Vec3(0.2, 0.2, 0.34);
  c.obstacles = nbs::test::obstacle_boxes(space, cs);
  nbs::conformance::check_collision_checker_conformance(nbs::fcl::FclCollisionChecker(space, cs), c, 5);
}
