// SPDX-License-Identifier: BSD-3-Clause
// Collision model of workspace modeling (Sec. 5.5): rules against a brute-force oracle, the closed surface mesh.
#include "nbs_catch.hpp"

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>
#include <tuple>
#include <utility>
#include <vector>

#include "nbs/io/read_stl.hpp"
#include "nbs/workspace/collision_model.hpp"
#include "support/collision_scene.hpp"

namespace {
using nbs::VoxelKey;
using LogOddsCollisionSpace = nbs::ProbabilisticVoxelSpace<nbs::HashedBlockBackend<nbs::LogOddsState>, nbs::LogOddsModel>;
using KeySet = std::set<std::tuple<int, int, int>>;
constexpr int kOffsets[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};

std::tuple<int, int, int> t(const VoxelKey& k) { return {k.x, k.y, k.z}; }

// Oracle: the voxels of the scene after rules 1 and 2, written out by hand.
KeySet scene_obstacles(bool include_unknown) {
  KeySet s;
  for (int z = 0; z < 4; ++z)
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 4; ++x) s.insert({x, y, z});
  if (include_unknown) {
    s.insert(t(nbs::test::kSceneUnknown));
    s.insert(t(nbs::test::kSceneUnobserved));
  }
  return s;
}
// Oracle: exposed face mask of k in s (brute force over the 6 neighbours).
int exposed(const KeySet& s, const std::tuple<int, int, int>& k) {
  int m = 0;
  for (int f = 0; f < 6; ++f)
    if (!s.contains({std::get<0>(k) + kOffsets[f][0], std::get<1>(k) + kOffsets[f][1], std::get<2>(k) + kOffsets[f][2]}))
      m |= 1 << f;
  return m;
}
}  // namespace

TEST_CASE("Collision model: low p dropped, unknown by option, floating blob and inner voxels removed",
          "[space][collision_model]") {
  LogOddsCollisionSpace space(nbs::test::kSceneVoxel, nbs::test::kSceneBox);
  nbs::test::fill_collision_scene(space);
  for (const bool include_unknown : {true, false}) {
    CAPTURE(include_unknown);
    nbs::CollisionModelSetting setting;
    setting.include_unknown = include_unknown;
    const nbs::CollisionModel m = nbs::build_collision_model(space, setting);
    const KeySet full = scene_obstacles(include_unknown);
    KeySet expected;  // inner = all 6 neighbours obstacles (brute force)
    for (const auto& k : full)
      if (exposed(full, k) != 0) expected.insert(k);
    REQUIRE(full.size() - expected.size() == 8);  // the 2 × 2 × 2 inside of the cube
    REQUIRE(m.resolution_m == nbs::test::kSceneVoxel);
    REQUIRE(m.voxels.size() == expected.size());
    REQUIRE(m.exposed_faces.size() == m.voxels.size());
    for (std::size_t i = 0; i < m.voxels.size(); ++i) {
      REQUIRE(expected.contains(t(m.voxels[i])));
      REQUIRE(int{m.exposed_faces[i]} == exposed(full, t(m.voxels[i])));
      if (i > 0) REQUIRE(m.voxels[i - 1].pack() < m.voxels[i].pack());
    }
    const auto& c = m.counts;
    REQUIRE(c.candidates == full.size() + 2);  // + the blob
    REQUIRE(c.removed_floating == 2);
    REQUIRE(c.removed_small == 0);
    REQUIRE(c.removed_inner == 8);
    REQUIRE(c.groups_removed == 1);
    REQUIRE(c.groups_kept == (include_unknown ? 3u : 1u));
    REQUIRE(c.dropped_unknown == (include_unknown ? 0u : 1u));
    REQUIRE(c.dropped_free == 10 * 10 * 6 - 1 - 64 - 2 - 1);  // observed p = 0.1 and the p = 0.2 voxel
  }
  SECTION("switching the rules off") {
    nbs::CollisionModelSetting setting;
    setting.remove_floating = false;
    setting.remove_inner = false;
    setting.min_group_voxels = 3;  // removes the blob and the two single voxels, keeps the cube
    const auto m = nbs::build_collision_model(space, setting);
    REQUIRE(m.voxels.size() == 64);
    REQUIRE(m.counts.removed_small == 4);
    REQUIRE(m.counts.groups_removed == 3);
    REQUIRE(m.counts.removed_inner == 0);
  }
}

TEST_CASE("Collision mesh: closed, outward, one quad per exposed face", "[space][collision_model]") {
  LogOddsCollisionSpace space(nbs::test::kSceneVoxel, nbs::test::kSceneBox);
  nbs::test::fill_collision_scene(space);
  for (const bool include_unknown : {true, false}) {
    CAPTURE(include_unknown);
    nbs::CollisionModelSetting setting;
    setting.include_unknown = include_unknown;
    const auto m = nbs::build_collision_model(space, setting);
    const nbs::IndexedMesh mesh = nbs::collision_mesh(m);
    const KeySet full = scene_obstacles(include_unknown);
    std::size_t faces = 0;
    for (const auto& k : full) faces += static_cast<std::size_t>(__builtin_popcount(static_cast<unsigned>(exposed(full, k))));
    REQUIRE(faces == (include_unknown ? 96u + 12u : 96u));
    REQUIRE(mesh.triangles.size() == 2 * faces);
    // Closed and consistently oriented: each directed edge once, with its reverse once.
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    for (const auto& tri : mesh.triangles)
      for (int e = 0; e < 3; ++e) ++directed[{tri[e], tri[(e + 1) % 3]}];
    for (const auto& [e, n] : directed) {
      REQUIRE(n == 1);
      REQUIRE(directed.count({e.second, e.first}) == 1);
    }
    // Shared vertices: no two at the same place.
    std::set<std::tuple<double, double, double>> places;
    for (const auto& v : mesh.vertices) places.insert({v.x(), v.y(), v.z()});
    REQUIRE(places.size() == mesh.vertices.size());
    // Outward: enclosed volume (divergence theorem) = number of obstacle voxels · l_v³ > 0.
    double volume = 0.0;
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
      volume += mesh.corner(i, 0).dot(mesh.corner(i, 1).cross(mesh.corner(i, 2))) / 6.0;
    REQUIRE(volume == Approx(static_cast<double>(full.size()) * 1e-6).epsilon(1e-9));
    if (!include_unknown) {
      const nbs::Aabb box = mesh.bounds();
      REQUIRE((box.min - nbs::Vec3(0, 0, 0)).norm() < 1e-12);
      REQUIRE((box.max - nbs::Vec3(0.04, 0.04, 0.04)).norm() < 1e-12);
      REQUIRE_NOTHROW(mesh.validate());
      const auto path = std::filesystem::temp_directory_path() / "nbs_test_collision_mesh.stl";
      nbs::write_stl(path.string(), mesh);
      REQUIRE(nbs::read_stl(path.string()).triangles.size() == mesh.triangles.size());
      std::filesystem::remove(path);
    }
  }
}

TEST_CASE("Collision model: bad settings are rejected", "[space][collision_model]") {
  LogOddsCollisionSpace space(nbs::test::kSceneVoxel, nbs::test::kSceneBox);
  nbs::test::fill_collision_scene(space);
  const auto bad = [&](auto edit) {
    nbs::CollisionModelSetting s;
    edit(s);
    REQUIRE_THROWS_AS(nbs::build_collision_model(space, s), nbs::InvalidArgument);
  };
  bad([](auto& s) { s.free_below = -0.1; });
  bad([](auto& s) { s.occupied_from = 1.5; });
  bad([](auto& s) { s.occupied_from = 0.2; });  // below free_below
  bad([](auto& s) { s.floor_z_m = std::nan(""); });
  bad([](auto& s) { s.max_voxels = 0; });
  bad([](auto& s) { s.max_voxels = 50; });  // 66 voxels pass rule 1
  nbs::CollisionModel m = nbs::build_collision_model(space);
  m.exposed_faces.pop_back();
  REQUIRE_THROWS_AS(nbs::collision_mesh(m), nbs::InvalidArgument);
}
