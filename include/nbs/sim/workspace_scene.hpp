// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// A simulated workspace for workspace modeling (Sec. 5.5: "workspaces such as shelves, conveyor belts or
/// workbenches"): a floor, a shelf against the back wall of the workspace box, a conveyor-like table in its middle,
/// and objects (any meshes) standing on the shelf boards and the belt. Built from closed boxes (sim/test_objects.hpp)
/// and the given meshes; deterministic for a seed. World frame, metres, +z up, the floor's top at box.min.z; the
/// front of the workspace (where a platform drives) is the side y = box.min.y, the shelf stands at y = box.max.y.
/// The furniture is sized for a 4 × 4 × 2 m box and scaled uniformly with smaller boxes (tests use 1 × 1 × 0.5 m).

#include <algorithm>
#include <cstdint>
#include <numbers>
#include <random>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "nbs/core/detail/random.hpp"
#include "nbs/core/error.hpp"
#include "nbs/core/types.hpp"
#include "nbs/io/load_mesh.hpp"
#include "nbs/mesh/indexed_mesh.hpp"
#include "nbs/mesh/normalize.hpp"
#include "nbs/mesh/transformed_mesh.hpp"
#include "nbs/sim/test_objects.hpp"
#include "nbs/workspace/platform_pan_tilt.hpp"

namespace nbs {

/// Setting of make_workspace_scene.
struct WorkspaceSceneSetting {
  /// The workspace (the unknown area of the voxel space), world frame; the floor's top is box.min.z.
  Aabb box{Vec3(-2.0, -2.0, 0.0), Vec3(2.0, 2.0, 2.0)};
  std::uint64_t seed = 1;                ///< object choice, position and yaw
  std::uint32_t objects_per_surface = 3;  ///< objects on each shelf board and on the belt
  double object_size_m = 0.2;            ///< largest extent of each placed object (before the box scale)

  /// Throws InvalidArgument naming the value unless the box is finite with every side ≥ 0.5 m and object_size_m > 0.
  void validate() const {
    detail::require(box.min.allFinite() && box.max.allFinite(), "WorkspaceSceneSetting::box must be finite");
    const Vec3 size = box.max - box.min;
    detail::require(size.minCoeff() >= 0.5, "WorkspaceSceneSetting::box must be at least 0.5 m on every side, got ",
                    size.x(), " x ", size.y(), " x ", size.z(), " m");
    detail::require_positive("WorkspaceSceneSetting::object_size_m", object_size_m);
  }
};

/// One placed object: which input mesh, its pose (mesh frame after normalize_on_pedestal → world).
struct WorkspaceObject {
  std::size_t mesh_index = 0;
  Pose T_world_object = Pose::Identity();
};

/// The scene: one mesh of everything (closed parts, outward faces) and its ground truth.
struct WorkspaceScene {
  IndexedMesh mesh;                      ///< floor, furniture and objects, world frame
  Aabb box;                              ///< the workspace box of the setting
  std::vector<Aabb> furniture;           ///< floor slab, shelf parts, table parts, belt (solid boxes)
  std::vector<WorkspaceObject> objects;  ///< in placement order
  double scale = 1.0;                    ///< furniture scale: min(size.x / 4, size.y / 4, size.z / 2)
  /// Where a mobile platform explores it from (Sec. 5.5, "approximately centred in front of the workspace along the
  /// long side with the PTU facing the scene"): a line along x, 0.05 m in front of the box (the robot stands outside
  /// the workspace it models), offsets
  /// −1.5…1.5 m in 0.25 m steps (the step not below 0.05 m), the pan/tilt centre 1.3 m above the floor, looking
  /// at +y; the thesis's pan/tilt grid (all lengths × scale).
  PlatformPanTiltSetting platform;
};

/// Builds the workspace of `setting` with objects chosen (seeded) from `meshes` (each normalised upright: z up as
/// given, scaled to object_size_m · scale, random yaw). Shelf: 2 m wide, 0.4 m deep, 1.8 m high, boards at 0.05,
/// 0.5, 0.95, 1.4 m, its back 1 m in front of the back of the box (within an RGB-D camera's 3.5 m of the platform);
/// table: 2.4 × 0.6 m top at 0.8 m on four legs with a belt on it, 0.5 m in front of the box centre (all × scale). No object when `meshes` is empty. Throws
/// InvalidArgument for an invalid setting or mesh.
[[nodiscard]] inline WorkspaceScene make_workspace_scene(const WorkspaceSceneSetting& setting,
                                                         std::span<const IndexedMesh> meshes = {}) {
  setting.validate();
  for (const IndexedMesh& m : meshes) m.validate();
  WorkspaceScene scene;
  scene.box = setting.box;
  const Vec3 size = setting.box.max - setting.box.min;
  const double s = std::min({size.x() / 4.0, size.y() / 4.0, size.z() / 2.0});
  scene.scale = s;
  const double cx = setting.box.center().x(), cy = setting.box.center().y(), z0 = setting.box.min.z();
  auto part = [&](const Vec3& lo, const Vec3& hi) {
    detail::add_box(scene.mesh, lo, hi);
    scene.furniture.push_back(Aabb{lo, hi});
  };
  // Floor slab (its top is the floor).
  part(Vec3(setting.box.min.x(), setting.box.min.y(), z0 - 0.02 * s), Vec3(setting.box.max.x(), setting.box.max.y(), z0));
  // Shelf: two side panels, a back panel, five boards (the lowest just above the floor, the top one as a roof).
  const double sx0 = cx - 1.0 * s, sx1 = cx + 1.0 * s, sy1 = setting.box.max.y() - 1.0 * s, sy0 = sy1 - 0.4 * s;
  const double t = 0.02 * s, top = 1.8 * s;
  part(Vec3(sx0, sy0, z0), Vec3(sx0 + t, sy1, z0 + top));
  part(Vec3(sx1 - t, sy0, z0), Vec3(sx1, sy1, z0 + top));
  part(Vec3(sx0 + t, sy1 - t, z0), Vec3(sx1 - t, sy1, z0 + top));
  std::vector<std::pair<double, Aabb>> surfaces;  // (top z, footprint box) that objects stand on
  for (const double zb : {0.05, 0.5, 0.95, 1.4, 1.78}) {
    const Vec3 lo(sx0 + t, sy0, z0 + zb * s), hi(sx1 - t, sy1 - t, z0 + zb * s + t);
    part(lo, hi);
    if (zb < 1.7) surfaces.emplace_back(hi.z(), Aabb{lo, hi});
  }
  // Table with a belt: top 2.4 × 0.6 m at 0.8 m, legs 0.05 m square, belt 2.3 × 0.4 × 0.06 m.
  const double tx0 = cx - 1.2 * s, tx1 = cx + 1.2 * s, ty0 = cy - 0.5 * s, ty1 = cy + 0.1 * s;
  const double tz = z0 + 0.8 * s, leg = 0.05 * s;
  part(Vec3(tx0, ty0, tz - 0.04 * s), Vec3(tx1, ty1, tz));
  for (const double lx : {tx0, tx1 - leg})
    for (const double ly : {ty0, ty1 - leg}) part(Vec3(lx, ly, z0), Vec3(lx + leg, ly + leg, tz - 0.04 * s));
  const Vec3 belt_lo(cx - 1.15 * s, cy - 0.4 * s, tz), belt_hi(cx + 1.15 * s, cy + 0.0 * s, tz + 0.06 * s);
  part(belt_lo, belt_hi);
  surfaces.emplace_back(belt_hi.z(), Aabb{belt_lo, belt_hi});
  scene.platform.line_origin_m = Vec3(cx, setting.box.min.y() - 0.05 * s, z0);
  scene.platform.line_direction = Vec3::UnitX();
  scene.platform.platform_min_m = -1.5 * s;
  scene.platform.platform_max_m = 1.5 * s;
  scene.platform.platform_step_m = std::max(0.25 * s, 0.05);
  scene.platform.ptu_offset_m = Vec3(0.0, 0.0, 1.3 * s);
  scene.platform.base_view_direction = Vec3::UnitY();

  if (meshes.empty()) return scene;
  std::mt19937_64 rng(detail::splitmix64(setting.seed));
  auto u01 = [&rng] { return detail::uniform01(rng); };
  const double size_m = setting.object_size_m * s;
  for (const auto& [z_top, foot] : surfaces) {
    // One slot per object along x, so that objects on one surface never overlap (slot width ≥ the object's extent).
    const double width = foot.max.x() - foot.min.x(), depth = foot.max.y() - foot.min.y();
    const std::uint32_t n = std::min<std::uint32_t>(setting.objects_per_surface,
                                                    static_cast<std::uint32_t>(width / (1.5 * size_m)));
    if (n == 0 || depth < 1.5 * size_m) continue;
    const double slot = width / n;
    for (std::uint32_t k = 0; k < n; ++k) {
      WorkspaceObject obj;
      obj.mesh_index = static_cast<std::size_t>(u01() * static_cast<double>(meshes.size())) % meshes.size();
      IndexedMesh m = meshes[obj.mesh_index];
      normalize_on_pedestal(m, size_m);
      const double yaw = 2.0 * std::numbers::pi * u01();
      const double margin = 0.75 * size_m;  // half the diagonal of the footprint, at most
      const double x = foot.min.x() + slot * (k + 0.5) + (slot - 2.0 * margin) * (u01() - 0.5);
      const double y = foot.min.y() + margin + (depth - 2.0 * margin) * u01();
      obj.T_world_object.linear() = Eigen::AngleAxisd(yaw, Vec3::UnitZ()).toRotationMatrix();
      obj.T_world_object.translation() = Vec3(x, y, z_top);
      const IndexedMesh placed = transformed_mesh(m, obj.T_world_object);
      detail::append_part(scene.mesh, placed.vertices, placed.triangles);
      scene.objects.push_back(obj);
    }
  }
  return scene;
}

/// The objects of the example workspace (examples/nbs_workspace, benchmarks/bench_workspace): the mesh at
/// `bunny_path` (the bundled Stanford bunny, up axis y) normalized onto its pedestal at 0.16 m, then the mug, car and
/// table test objects. Throws FileError / InvalidArgument as load_mesh and normalize_on_pedestal.
[[nodiscard]] inline std::vector<IndexedMesh> example_workspace_objects(const std::string& bunny_path) {
  std::vector<IndexedMesh> meshes;
  IndexedMesh bunny = load_mesh(bunny_path);
  normalize_on_pedestal(bunny, 0.16, UpAxis::y);
  meshes.push_back(std::move(bunny));
  for (const TestObject o : {TestObject::mug, TestObject::car, TestObject::table}) meshes.push_back(make_test_object(o));
  return meshes;
}

}  // namespace nbs
