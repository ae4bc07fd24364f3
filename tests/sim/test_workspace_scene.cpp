// SPDX-License-Identifier: BSD-3-Clause
// The simulated workspace (sim/workspace_scene.hpp): furniture inside the box and on the floor, objects standing on
// a shelf board or the belt without overlapping each other, deterministic for a seed, scaled with the box.

#include "nbs_catch.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "nbs/sim/test_objects.hpp"
#include "nbs/sim/workspace_scene.hpp"

using namespace nbs;

namespace {

// The axis-aligned box of the vertices of `m` moved by T.
Aabb placed_box(const IndexedMesh& m, const Pose& T) {
  Aabb b;
  for (const Vec3& v : m.vertices) b.extend(T * v);
  return b;
}

bool overlap_xy(const Aabb& a, const Aabb& b) {
  return a.min.x() < b.max.x() && b.min.x() < a.max.x() && a.min.y() < b.max.y() && b.min.y() < a.max.y();
}

}  // namespace

TEST_CASE("workspace scene: furniture in the box, objects on the surfaces, apart, seeded", "[sim][workspace]") {
  const std::array<IndexedMesh, 2> meshes{make_test_object(TestObject::mug), make_test_object(TestObject::car)};
  WorkspaceSceneSetting setting;
  setting.box = Aabb{Vec3(-0.5, -0.5, 0.0), Vec3(0.5, 0.5, 0.5)};  // a quarter of the 4 × 4 × 2 m workspace
  const WorkspaceScene scene = make_workspace_scene(setting, meshes);
  CHECK(scene.scale == Approx(0.25));
  REQUIRE_NOTHROW(scene.mesh.validate());
  // Floor slab + 3 shelf panels + 5 boards + table top + 4 legs + belt.
  REQUIRE(scene.furniture.size() == 15);
  CHECK(scene.furniture[0].max.z() == 0.0);
  for (std::size_t i = 1; i < scene.furniture.size(); ++i) {
    CAPTURE(i);
    CHECK(setting.box.contains(scene.furniture[i].min));
    CHECK(setting.box.contains(scene.furniture[i].max));
  }
  // Every object stands on the top of a board or the belt, inside the box, and no two on one surface overlap.
  REQUIRE(!scene.objects.empty());
  std::vector<Aabb> boxes;
  for (const WorkspaceObject& o : scene.objects) {
    IndexedMesh m = meshes[o.mesh_index];
    normalize_on_pedestal(m, setting.object_size_m * scene.scale);
    const Aabb b = placed_box(m, o.T_world_object);
    bool on_a_surface = false;
    for (const Aabb& f : scene.furniture)
      if (std::abs(b.min.z() - f.max.z()) < 1e-9 && b.min.x() >= f.min.x() - 1e-9 && b.max.x() <= f.max.x() + 1e-9 &&
          b.min.y() >= f.min.y() - 1e-9 && b.max.y() <= f.max.y() + 1e-9)
        on_a_surface = true;
    CHECK(on_a_surface);
    CHECK(setting.box.contains(b.min));
    CHECK(setting.box.contains(b.max));
    for (const Aabb& other : boxes)
      if (std::abs(other.min.z() - b.min.z()) < 1e-9) CHECK_FALSE(overlap_xy(other, b));
    boxes.push_back(b);
  }
  // The platform drives in front of the box, within its width, looking into it.
  REQUIRE_NOTHROW(scene.platform.validate());
  CHECK(scene.platform.base_view_direction == Vec3::UnitY());
  for (const double s : {scene.platform.platform_min_m, scene.platform.platform_max_m}) {
    const Vec3 p = scene.platform.line_origin_m + s * scene.platform.line_direction;
    CHECK(p.y() < setting.box.min.y());
    CHECK(p.x() > setting.box.min.x());
    CHECK(p.x() < setting.box.max.x());
  }
  // Seeded: the same seed gives the same scene, another seed another one.
  const WorkspaceScene again = make_workspace_scene(setting, meshes);
  CHECK(again.mesh.vertices == scene.mesh.vertices);
  setting.seed = 2;
  const WorkspaceScene other = make_workspace_scene(setting, meshes);
  CHECK(other.mesh.vertices != scene.mesh.vertices);
  CHECK(other.furniture.size() == scene.furniture.size());
}

TEST_CASE("workspace scene: bad settings are rejected", "[sim][workspace]") {
  WorkspaceSceneSetting s;
  s.box = Aabb{Vec3(0, 0, 0), Vec3(0.4, 1, 1)};
  CHECK_THROWS_AS(make_workspace_scene(s), InvalidArgument);
  s = {};
  s.object_size_m = 0.0;
  CHECK_THROWS_AS(make_workspace_scene(s), InvalidArgument);
  s = {};
  s.box.max.x() = std::numeric_limits<double>::infinity();
  CHECK_THROWS_AS(make_workspace_scene(s), InvalidArgument);
  CHECK(make_workspace_scene(WorkspaceSceneSetting{}).objects.empty());  // no meshes, no objects
}
