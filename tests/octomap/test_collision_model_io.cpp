// SPDX-License-Identifier: BSD-3-Clause
// Collision model as an OctoMap tree and file (.bt / .ot): round trip through OctoMap's own readers; the model of the
// same space on the OcTree backend (voxel-wise path) equals the native one (block-wise path).
#include "nbs_catch.hpp"

#include <octomap/AbstractOcTree.h>

#include <filesystem>
#include <memory>
#include <set>
#include <tuple>

#include "nbs/octomap/collision_model_io.hpp"
#include "space/support/collision_scene.hpp"

namespace {
using nbs::VoxelKey;
using Native = nbs::ProbabilisticVoxelSpace<nbs::HashedBlockBackend<nbs::LogOddsState>, nbs::LogOddsModel>;
using OnOctree = nbs::ProbabilisticVoxelSpace<::octomap::OcTree, nbs::LogOddsModel>;
using KeySet = std::set<std::tuple<int, int, int>>;

// Voxels covered by the occupied leaves of `tree` (pruned leaves expanded, via the OcTree backend's for_each).
KeySet occupied_voxels(const ::octomap::OcTree& tree) {
  KeySet s;
  nbs::for_each_voxel(tree, [&](const VoxelKey& k, const nbs::LogOddsState& st) {
    if (st.log_odds > 0.0f) s.insert({k.x, k.y, k.z});
  });
  return s;
}
std::set<std::tuple<double, double, double, unsigned>> occupied_leaves(const ::octomap::OcTree& tree) {
  std::set<std::tuple<double, double, double, unsigned>> s;
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it)
    if (tree.isNodeOccupied(*it)) s.insert({it.getX(), it.getY(), it.getZ(), it.getDepth()});
  return s;
}
nbs::CollisionModel scene_model() {
  Native space(nbs::test::kSceneVoxel, nbs::test::kSceneBox);
  nbs::test::fill_collision_scene(space);
  return nbs::build_collision_model(space);
}
}  // namespace

TEST_CASE("Collision model on the OcTree backend equals the native one", "[octomap][collision_model]") {
  OnOctree space(nbs::test::kSceneVoxel, nbs::test::kSceneBox);
  nbs::test::fill_collision_scene(space);
  const auto a = nbs::build_collision_model(space), b = scene_model();
  REQUIRE(a.voxels == b.voxels);
  REQUIRE(a.exposed_faces == b.exposed_faces);
  REQUIRE(a.counts.candidates == b.counts.candidates);
  REQUIRE(a.counts.removed_inner == b.counts.removed_inner);
}

TEST_CASE("Collision octree: .bt and .ot round trip through OctoMap", "[octomap][collision_model]") {
  const nbs::CollisionModel m = scene_model();
  REQUIRE(m.voxels.size() == 58);  // 64 + 2 − 8 (see tests/space/test_collision_model.cpp)
  KeySet expected;
  for (const VoxelKey& k : m.voxels) expected.insert({k.x, k.y, k.z});
  const auto tree = nbs::octomap::to_collision_octree(m);
  REQUIRE(tree->getResolution() == m.resolution_m);
  REQUIRE(occupied_voxels(*tree) == expected);
  for (std::size_t i = 0; i < m.size(); ++i) {  // leaf centres are the voxel centres (none pruned here)
    const auto* n = tree->search(m.center(i).x(), m.center(i).y(), m.center(i).z());
    REQUIRE(n != nullptr);
    REQUIRE(tree->isNodeOccupied(n));
  }
  const auto dir = std::filesystem::temp_directory_path();
  for (const char* name : {"nbs_test_collision.bt", "nbs_test_collision.OT"}) {
    CAPTURE(name);
    const auto path = dir / name;
    std::filesystem::remove(path);
    nbs::octomap::write_collision_octree(m, path);
    REQUIRE(!std::filesystem::exists(path.string() + ".tmp"));
    std::unique_ptr<::octomap::OcTree> back;
    if (path.extension() == ".bt") {
      back = std::make_unique<::octomap::OcTree>(path.string());
    } else {
      back.reset(dynamic_cast<::octomap::OcTree*>(::octomap::AbstractOcTree::read(path.string())));
    }
    REQUIRE(back != nullptr);
    REQUIRE(back->getResolution() == m.resolution_m);
    REQUIRE(occupied_voxels(*back) == expected);
    REQUIRE(occupied_leaves(*back) == occupied_leaves(*tree));
    std::filesystem::remove(path);
  }
}

TEST_CASE("Collision octree: bad extension, unwritable path, key out of range", "[octomap][collision_model]") {
  const nbs::CollisionModel m = scene_model();
  const auto dir = std::filesystem::temp_directory_path();
  const auto stl = dir / "nbs_test_collision.stl";
  std::filesystem::remove(stl);
  REQUIRE_THROWS_AS(nbs::octomap::write_collision_octree(m, stl), nbs::InvalidArgument);
  REQUIRE(!std::filesystem::exists(stl));
  const auto missing = dir / "nbs_test_collision_no_such_dir" / "model.bt";
  REQUIRE_THROWS_AS(nbs::octomap::write_collision_octree(m, missing), nbs::FileError);
  REQUIRE(!std::filesystem::exists(missing.parent_path()));
  nbs::CollisionModel far = m;
  far.voxels.push_back({40000, 0, 0});
  far.exposed_faces.push_back(nbs::kAllFaces);
  REQUIRE_THROWS_AS(nbs::octomap::to_collision_octree(far), nbs::InvalidArgument);
}
