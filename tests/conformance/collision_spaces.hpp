// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Obstacle spaces for the CollisionChecker conformance suites (core and FCL).
#include <cstdint>
#include <set>

#include "nbs/candidates/collision.hpp"
#include "nbs/space/concepts.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"
#include "nbs/space/ray_cast.hpp"
#include "nbs/space/unknown_area_grid.hpp"

namespace nbs::conformance {

/// A hand-built VoxelSpace: 1 cm voxels, bounds [−10, 10)³ keys, p = 0.9 on a listed set, 0.01 elsewhere (State:
/// 0 unknown, 1 free, 2 occupied; integrate marks the end voxels occupied; ray casts by walk_ray_generic).
struct HandBuiltObstacles : UnknownAreaGrid {
  using State = std::uint8_t;
  std::set<std::uint64_t> obstacles;
  HandBuiltObstacles(double l = 0.01, const Aabb& box = {Vec3::Constant(-0.1), Vec3::Constant(0.0999)})
      : UnknownAreaGrid(l, box) {}
  /// Two crossing bars through the origin region and a single voxel high up.
  static HandBuiltObstacles cross() {
    HandBuiltObstacles s;
    for (int i = -8; i < 8; ++i) {
      s.obstacles.insert(VoxelKey{i, 0, 5}.pack());
      s.obstacles.insert(VoxelKey{0, i, 8}.pack());
    }
    s.obstacles.insert(VoxelKey{5, 5, 9}.pack());
    return s;
  }
  IntegrationStats integrate(const Scan& scan) {
    scan.validate();
    for (const Vec3& p : scan.points)
      if (const auto k = grid().key_of(p); k && bounds_keys().contains(*k)) obstacles.insert(k->pack());
    return {};
  }
  [[nodiscard]] const HandBuiltObstacles& model() const { return *this; }
  [[nodiscard]] static double probability(State s) { return s == 0 ? 0.5 : s == 1 ? 0.01 : 0.9; }
  [[nodiscard]] static bool occupied_state(State s) { return s == 2; }
  [[nodiscard]] bool occupied(State s) const { return occupied_state(s); }
  [[nodiscard]] State state(const VoxelKey& k) const {
    return !bounds_keys().contains(k) ? State{0} : obstacles.count(k.pack()) ? State{2} : State{1};
  }
  [[nodiscard]] double probability(const VoxelKey& k) const { return obstacles.count(k.pack()) ? 0.9 : 0.01; }
  [[nodiscard]] double probability(const Vec3& x) const {
    const auto k = grid().key_of(x);
    return k ? probability(*k) : 0.5;
  }
  [[nodiscard]] bool occupied(const VoxelKey& k) const { return obstacles.count(k.pack()) != 0; }
  [[nodiscard]] bool observed(const VoxelKey& k) const { return bounds_keys().contains(k); }
  template <class F>
  void for_each(F&& f) const {
    const KeyBox b = bounds_keys();
    for (int z = b.min.z; z <= b.max.z; ++z)
      for (int y = b.min.y; y <= b.max.y; ++y)
        for (int x = b.min.x; x <= b.max.x; ++x) f(VoxelKey{x, y, z}, state(VoxelKey{x, y, z}));
  }
  template <class Visit>
  RaycastResult cast_ray(const Ray& ray, Visit&& visit) const {
    return walk_ray_generic(*this, ray, visit);
  }
};
static_assert(VoxelSpace<HandBuiltObstacles>);

/// Occupied plate at z ∈ [0.05, 0.06), a free column (p = 0.01) above it, unknown voxels elsewhere in the bounds.
inline ProbabilisticVoxelSpace<> plate_space() {
  ThesisModel::Setting ms;
  ms.prob_free = 0.01;
  ProbabilisticVoxelSpace<> space(0.01, Aabb{Vec3(-0.1, -0.1, 0.0), Vec3(0.1, 0.1, 0.2)}, ThesisModel(ms));
  Scan scan;
  Pose o = Pose::Identity();
  o.translation() = Vec3(0, 0, 0.6);
  scan.profile_poses.push_back(o);
  for (int y = -6; y < 6; ++y)
    for (int x = -6; x < 6; ++x) scan.add_point(space.grid().center({x, y, 5}), 0);
  (void)space.integrate(scan);
  return space;
}

}  // namespace nbs::conformance
