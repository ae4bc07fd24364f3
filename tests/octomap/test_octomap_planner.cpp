// SPDX-License-Identifier: BSD-3-Clause
// The OctoMap space as a VoxelSpace: the conformance suite, and NbsPlanner run end to end with it. Oracle: the same
// planner over the native hashed-block space with the same LogOddsModel (identical voxel states, see
// test_octomap_backend.cpp) plans the same scans, step for step.
#include "nbs_catch.hpp"

#include "nbs/octomap/octree_backend.hpp"
#include "nbs/planner/nbs_planner.hpp"
#include "nbs/planner/simulation_loop.hpp"
#include "nbs/sensor/presets.hpp"
#include "nbs/space/log_odds_model.hpp"
#include "octomap/classification_agreement.hpp"
#include "planner/support/analytic_scanner.hpp"
#include "planner/support/same_plan.hpp"
#include "space/support/voxel_space_conformance.hpp"

namespace {
using OnOctree = nbs::ProbabilisticVoxelSpace<::octomap::OcTree, nbs::LogOddsModel>;
template <class Space>
using PlannerOn = nbs::NbsPlanner<nbs::IgQualityUtility, nbs::BoundaryHoleSpace, nbs::LaserStripeProfiler,
                                  nbs::NoCollisions, nbs::DefaultTermination, Space>;
}  // namespace

static_assert(nbs::VoxelSpace<OnOctree>);
static_assert(!nbs::BlockBackend<::octomap::OcTree>);

TEST_CASE("the OctoMap space passes the VoxelSpace conformance suite", "[octomap][concept]") {
  nbs::test::check_voxel_space_conformance<OnOctree>();
}

TEST_CASE("NbsPlanner over the OctoMap space plans the scans of the native space", "[octomap][planner]") {
  const nbs::test::SphereOnPedestal sphere;
  const nbs::Aabb box{nbs::Vec3(-0.06, -0.06, 0.0), nbs::Vec3(0.06, 0.06, 0.10)};
  nbs::LaserStripeProfiler lsp = nbs::presets::dlr_lsp();
  lsp.points_per_profile = 200;
  lsp.profile_spacing_m = 0.002;
  nbs::SimulationSetting sim;
  sim.seed = 3;
  sim.max_scans = 4;
  PlannerOn<OnOctree> tree({}, lsp, box);
  PlannerOn<nbs::test::NativeLogOddsSpace> native({}, lsp, box);
  const auto a = nbs::run_simulation(tree, sphere, sim);
  const auto b = nbs::run_simulation(native, sphere, sim);
  REQUIRE(a.records.size() == 4);
  nbs::test::check_same_plan(a, b);
  CHECK(tree.features().size() == native.features().size());
  CHECK(tree.features().size() > 0);
  CHECK(a.records.back().integration.estimated_coverage > a.records.front().integration.estimated_coverage);
}
