// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A hand-built voxel space for the collision model tests (l_v = 1 cm, bounds keys [0, 9]² × [0, 5], floor z = 0):
// every voxel observed free (p = 0.1) except: a solid 4 × 4 × 4 cube on the floor (keys 0..3, p = 0.9), a
// floating 2-voxel blob (p = 0.9), an observed unknown voxel on the floor (p = 0.5), a never-observed voxel on the
// floor, a p = 0.2 voxel.
#include <cstdint>

#include "nbs/space/log_odds_model.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"

namespace nbs::test {

inline constexpr double kSceneVoxel = 0.01;
inline const Aabb kSceneBox{Vec3(0.0, 0.0, 0.0), Vec3(0.0999, 0.0999, 0.0599)};
inline constexpr VoxelKey kSceneBlob[2] = {{7, 2, 3}, {8, 2, 3}};
inline constexpr VoxelKey kSceneUnknown{7, 5, 0};     // observed, p = 0.5
inline constexpr VoxelKey kSceneUnobserved{8, 8, 0};  // never observed
inline constexpr VoxelKey kSceneLow{0, 8, 0};         // p = 0.2

/// Fills `space` (any backend with LogOddsState) as described above.
template <class Space>
void fill_collision_scene(Space& space) {
  const auto put = [&](const VoxelKey& k, double p) {
    set_voxel_state(space.mutable_backend(), k, LogOddsState{LogOddsModel::logodds(p)});
  };
  const KeyBox kb = space.bounds_keys();
  for (std::int32_t z = kb.min.z; z <= kb.max.z; ++z)
    for (std::int32_t y = kb.min.y; y <= kb.max.y; ++y)
      for (std::int32_t x = kb.min.x; x <= kb.max.x; ++x)
        if (!(VoxelKey{x, y, z} == kSceneUnobserved)) put({x, y, z}, 0.1);
  for (std::int32_t z = 0; z < 4; ++z)
    for (std::int32_t y = 0; y < 4; ++y)
      for (std::int32_t x = 0; x < 4; ++x) put({x, y, z}, 0.9);
  for (const VoxelKey& k : kSceneBlob) put(k, 0.9);
  put(kSceneUnknown, 0.5);
  put(kSceneLow, 0.2);
}

}  // namespace nbs::test
