// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Export of a ProbabilisticVoxelSpace as an `octomap::OcTree` obstacle model for collision checking (e.g. FCL's
/// `fcl::OcTree`): every voxel in the space's bounds with p > min_probability — occupied *or unknown* — becomes an
/// occupied leaf, every other voxel in the bounds a free leaf (Sec. 3.2.2 plans with p > 0.05 as obstacle).

#include <octomap/OcTree.h>

#include <cstdint>
#include <memory>

#include "nbs/octomap/octree_backend.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"

namespace nbs::octomap {

/// Builds the obstacle tree (same resolution; occupied leaves log-odds of 0.971, free 0.1192; pruned).
/// Throws InvalidArgument if min_probability ∉ [0, 1), if the bounds hold more than max_voxels voxels or if they
/// exceed OctoMap's key range (±2^15 voxels).
template <class B, class M>
[[nodiscard]] std::unique_ptr<::octomap::OcTree> to_obstacle_octree(const ProbabilisticVoxelSpace<B, M>& space,
                                                                    double min_probability = 0.05,
                                                                    std::uint64_t max_voxels = 50'000'000) {
  detail::require(min_probability >= 0.0 && min_probability < 1.0, "min_probability must be in [0, 1), got ",
                  min_probability);
  const KeyBox kb = space.bounds_keys();
  detail::require(kb.volume() <= max_voxels, "to_obstacle_octree: ", kb.volume(), " voxels exceed max_voxels = ",
                  max_voxels);
  detail::require(to_octree_key(kb.min) && to_octree_key(kb.max),
                  "to_obstacle_octree: bounds exceed OctoMap's key range");
  auto tree = std::make_unique<::octomap::OcTree>(space.resolution_m());
  const float occ = LogOddsModel::logodds(0.971), free = LogOddsModel::logodds(0.1192);
  for (std::int32_t z = kb.min.z; z <= kb.max.z; ++z)
    for (std::int32_t y = kb.min.y; y <= kb.max.y; ++y)
      for (std::int32_t x = kb.min.x; x <= kb.max.x; ++x) {
        const VoxelKey k{x, y, z};
        tree->setNodeValue(*to_octree_key(k), space.probability(k) > min_probability ? occ : free, true);
      }
  tree->updateInnerOccupancy();
  tree->prune();
  return tree;
}

}  // namespace nbs::octomap
