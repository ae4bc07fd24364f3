// SPDX-License-Identifier: BSD-3-Clause
// The VoxelSpace concept (nbs/space/concepts.hpp): its conformance suite on every space model in the core and on a
// space written by a user in a few lines, example 05's MyVoxelSpace (the OctoMap space runs the same suite in
// tests/octomap).
#include "nbs_catch.hpp"

#include "nbs/space/hashed_block_backend.hpp"
#include "nbs/space/log_odds_model.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"
#include "my_voxel_space.hpp"
#include "support/voxel_space_conformance.hpp"

static_assert(nbs::VoxelSpace<MyVoxelSpace>);
static_assert(!nbs::BatchRayCastingSpace<MyVoxelSpace>);
static_assert(!nbs::NoiseModelSpace<MyVoxelSpace>);
static_assert(nbs::BatchRayCastingSpace<nbs::ProbabilisticVoxelSpace<>>);
static_assert(nbs::NoiseModelSpace<nbs::ProbabilisticVoxelSpace<>>);
static_assert(nbs::BlockBackend<nbs::HashedBlockBackend<nbs::ThesisState>>);
static_assert(nbs::ParallelIntegratingSpace<nbs::ProbabilisticVoxelSpace<>>);
static_assert(!nbs::ParallelIntegratingSpace<MyVoxelSpace>);
static_assert(nbs::ConcurrentBlockBackend<nbs::HashedBlockBackend<nbs::ThesisState>>);

TEMPLATE_TEST_CASE("VoxelSpace conformance", "[space][concept]", nbs::ProbabilisticVoxelSpace<>,
                   (nbs::ProbabilisticVoxelSpace<nbs::HashedBlockBackend<nbs::LogOddsState>, nbs::LogOddsModel>),
                   MyVoxelSpace) {
  nbs::test::check_voxel_space_conformance<TestType>();
}
