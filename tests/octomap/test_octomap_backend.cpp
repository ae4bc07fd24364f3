// SPDX-License-Identifier: BSD-3-Clause
// The OctoMap backend: conformance suite, identical results to the native backend, OctoMap itself as oracle.
#include "nbs_catch.hpp"

#include "nbs/octomap/insert_scan.hpp"
#include "nbs/octomap/obstacle_model.hpp"
#include "nbs/octomap/octree_backend.hpp"
#include "nbs/space/log_odds_model.hpp"
#include "octomap/classification_agreement.hpp"
#include "space/support/backend_conformance.hpp"
#include "space/support/synthetic_scan.hpp"

namespace {
using nbs::Vec3;
using nbs::VoxelKey;
using Native = nbs::test::NativeLogOddsSpace;
using OnOctree = nbs::ProbabilisticVoxelSpace<::octomap::OcTree, nbs::LogOddsModel>;
// Float-representable box so that OctoMap's float BBX test and ours agree.
const nbs::Aabb kBox{nbs::test::to_float(Vec3(-0.1, -0.1, 0.0)), nbs::test::to_float(Vec3(0.1, 0.1, 0.2))};
const nbs::test::SphereLspSetup kSetup{.profiles = 40, .rays_per_profile = 120, .noise_sigma_m = 0.0003};

}  // namespace

TEST_CASE("octomap::OcTree passes the backend conformance suite", "[octomap][backend]") {
  nbs::test::check_backend_conformance<::octomap::OcTree>(
      0.005, [](int i) { return nbs::LogOddsState{0.001f * static_cast<float>(i) - 3.0f}; });
}

TEST_CASE("PVS on OcTree and on native blocks produce identical states", "[octomap][pvs]") {
  Native native(0.004, kBox);
  OnOctree tree(0.004, kBox);
  for (int i = 0; i < 5; ++i) {
    const auto scan = nbs::test::sphere_lsp_scan(kSetup, nbs::test::ring_position(kSetup, i, 5, 0.3), 100 + i);
    const auto a = native.integrate(scan), b = tree.integrate(scan);
    REQUIRE(a.voxel_updates == b.voxel_updates);
    REQUIRE(a.voxels_same_scan == b.voxels_same_scan);
  }
  REQUIRE(nbs::observed_count(native.backend()) == nbs::observed_count(tree.backend()));
  native.for_each([&](const VoxelKey& k, const nbs::LogOddsState& s) { REQUIRE(tree.state(k) == s); });
}

TEST_CASE("native log-odds space classifies >= 99.9 % of voxels like OctoMap's insertion", "[octomap][oracle]") {
  Native native(0.004, kBox);
  auto ref = nbs::octomap::bbx_limited_octree(0.004, kBox);
  for (int i = 0; i < 6; ++i) {
    const auto scan = nbs::test::sphere_lsp_scan(kSetup, nbs::test::ring_position(kSetup, i, 6, 0.3), 200 + i);
    (void)native.integrate(scan);
    nbs::octomap::insert_scan(ref, scan);
  }
  const auto r = nbs::test::classification_agreement(native, ref);
  INFO("voxels " << r.total << ", identical " << r.same << ", only in OctoMap " << r.only_ref);
  REQUIRE(r.total > 20000);
  REQUIRE(r.occupied > 500);
  REQUIRE(r.share() >= 0.999);
}

TEST_CASE("obstacle model: occupied and unknown voxels become occupied leaves", "[octomap][obstacle]") {
  nbs::ProbabilisticVoxelSpace<> space(0.01, kBox);
  for (int i = 0; i < 3; ++i)
    (void)space.integrate(nbs::test::sphere_lsp_scan(kSetup, nbs::test::ring_position(kSetup, i, 3, 0.3), i));
  const auto tree = nbs::octomap::to_obstacle_octree(space, 0.45);  // free after one pass: p = 0.4
  std::size_t obstacles = 0, free = 0;
  const nbs::KeyBox kb = space.bounds_keys();
  for (int z = kb.min.z; z <= kb.max.z; ++z)
    for (int y = kb.min.y; y <= kb.max.y; ++y)
      for (int x = kb.min.x; x <= kb.max.x; ++x) {
        const VoxelKey k{x, y, z};
        const auto* n = tree->search(*nbs::octomap::to_octree_key(k));
        REQUIRE(n != nullptr);
        REQUIRE(tree->isNodeOccupied(n) == (space.probability(k) > 0.45));
        (tree->isNodeOccupied(n) ? obstacles : free) += 1;
      }
  REQUIRE(free > 100);
  REQUIRE(obstacles > 100);
  REQUIRE_THROWS_AS(nbs::octomap::to_obstacle_octree(space, 1.5), nbs::InvalidArgument);
}
