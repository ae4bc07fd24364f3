#pragma once
// Obstacle spaces for the CollisionChecker conformance suites (core and FCL).
#include <set>

#include "nbs/candidates/collision.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"

namespace nbs::conformance {

/// A hand-built ObstacleVoxelSpace: 1 cm voxels, bounds [−10, 10)³ keys, p = 0.9 on a listed set, 0.01 elsewhere.
struct HandBuiltObstacles {
  VoxelGrid grid_{0.01};
  std::set<std::uint64_t> occupied;
  /// Two crossing bars through the origin region and a single voxel high up.
  static HandBuiltObstacles cross() {
    HandBuiltObstacles s;
    for (int i = -8; i < 8; ++i) {
      s.occupied.insert(VoxelKey{i, 0, 5}.pack());
      s.occupied.insert(VoxelKey{0, i, 8}.pack());
    }
    s.occupied.insert(VoxelKey{5, 5, 9}.pack());
    return s;
  }
  [[nodiscard]] double probability(const VoxelKey& k) const { return occupied.count(k.pack()) ? 0.9 : 0.01; }
  [[nodiscard]] KeyBox bounds_keys() const { return KeyBox{VoxelKey{-10, -10, -10}, VoxelKey{9, 9, 9}}; }
  [[nodiscard]] const VoxelGrid& grid() const { return grid_; }
  [[nodiscard]] double resolution_m() const { return grid_.resolution_m(); }
};
static_assert(ObstacleVoxelSpace<HandBuiltObstacles>);

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
