// SPDX-License-Identifier: BSD-3-Clause
// NbsPlanner with the FCL collision checker: the planner updates it from the voxel space after every scan
// (SpaceTrackingCollisionChecker). Oracle: the core VoxelCollisionChecker reads the live space, so after the loop
// both must agree on poses whose head box is not near an obstacle boundary; before any update the FCL snapshot
// of the all-unknown space calls every pose inside the box a collision.
#include "nbs_catch.hpp"

#include <random>

#include "box_oracle.hpp"
#include "nbs/fcl/collision_checker.hpp"
#include "nbs/planner/nbs_planner.hpp"
#include "nbs/planner/simulation_loop.hpp"
#include "nbs/sensor/presets.hpp"
#include "planner/support/analytic_scanner.hpp"

static_assert(nbs::SpaceTrackingCollisionChecker<nbs::fcl::FclCollisionChecker, nbs::ProbabilisticVoxelSpace<>>);
static_assert(!nbs::SpaceTrackingCollisionChecker<nbs::NoCollisions, nbs::ProbabilisticVoxelSpace<>>);

TEST_CASE("NbsPlanner keeps the FCL checker updated from the voxel space", "[fcl][planner]") {
  using Planner = nbs::NbsPlanner<nbs::IgQualityUtility, nbs::BoundaryHoleSpace, nbs::LaserStripeProfiler,
                                  nbs::fcl::FclCollisionChecker>;
  const nbs::test::SphereOnPedestal sphere;
  const nbs::Aabb box{nbs::Vec3(-0.06, -0.06, 0.0), nbs::Vec3(0.06, 0.06, 0.10)};
  nbs::LaserStripeProfiler lsp = nbs::presets::dlr_lsp();
  lsp.points_per_profile = 200;
  lsp.profile_spacing_m = 0.002;
  Planner planner({}, lsp, box);
  // A 1 cm head, and voxels passed by one beam (p = 0.4) count as free, so that poses inside the box can be free
  // after three scans (the default 0.05 takes ≈ 7 passes of the thesis model).
  nbs::CollisionSetting small;
  small.head.size_m = nbs::Vec3(0.01, 0.01, 0.01);
  small.head.center_m = nbs::Vec3::Zero();
  small.obstacle_probability = 0.45;
  planner.collision = nbs::fcl::FclCollisionChecker(planner.space(), small);
  std::mt19937_64 rng(7);
  std::vector<nbs::Pose> poses;
  for (int i = 0; i < 400; ++i) poses.push_back(nbs::test::random_pose(rng, box.min, box.max));
  int before = 0;
  for (const nbs::Pose& p : poses) before += planner.collision.collides(p) ? 1 : 0;
  CHECK(before == static_cast<int>(poses.size()));  // the empty space is all unknown: all obstacle

  nbs::SimulationSetting sim;
  sim.seed = 2;
  sim.max_scans = 3;
  const auto res = nbs::run_simulation(planner, sphere, sim);
  REQUIRE(res.records.size() == 3);
  const nbs::VoxelCollisionChecker<nbs::ProbabilisticVoxelSpace<>> core(planner.space(), small);
  int free_core = 0, agree = 0;
  for (const nbs::Pose& p : poses) {
    const bool c = core.collides(p);
    free_core += c ? 0 : 1;
    agree += c == planner.collision.collides(p) ? 1 : 0;
  }
  INFO("free (core) " << free_core << ", agree " << agree << " of " << poses.size());
  CHECK(free_core > 20);                                   // the scans freed space the update must show
  CHECK(agree >= static_cast<int>(poses.size()) - 8);     // up to FCL's touching tolerance
}
