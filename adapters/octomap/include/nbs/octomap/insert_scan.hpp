// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Reference insertion of an nbs::Scan into an `octomap::OcTree` with OctoMap's own ray casting, treating the whole
/// scan as one update (each voxel updated once, end points preferred), i.e. the semantics of
/// ProbabilisticVoxelSpace<..., LogOddsModel>. Used as the oracle in tests and benchmarks.

#include <octomap/OcTree.h>

#include <vector>

#include "nbs/core/scan.hpp"
#include "nbs/core/types.hpp"

namespace nbs::octomap {

/// An OcTree at `resolution_m` (metres) whose updates are limited to `box` (world frame, metres; OctoMap tests its
/// bounding box in float), the counterpart of ProbabilisticVoxelSpace's unknown-area box.
inline ::octomap::OcTree bbx_limited_octree(double resolution_m, const Aabb& box) {
  ::octomap::OcTree t(resolution_m);
  ::octomap::point3d lo(static_cast<float>(box.min.x()), static_cast<float>(box.min.y()), static_cast<float>(box.min.z()));
  ::octomap::point3d hi(static_cast<float>(box.max.x()), static_cast<float>(box.max.y()), static_cast<float>(box.max.z()));
  t.setBBXMin(lo);  // OctoMap takes non-const references
  t.setBBXMax(hi);
  t.useBBXLimit(true);
  return t;
}

/// Groups the scan's points by profile and accumulates `computeUpdate` over all profiles, then applies the free
/// and occupied updates. Points are converted to float (OctoMap's point type).
inline void insert_scan(::octomap::OcTree& tree, const Scan& scan) {
  std::vector<::octomap::Pointcloud> clouds(scan.profile_poses.size());
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const Vec3& p = scan.points[i];
    clouds[scan.profile_of_point[i]].push_back(static_cast<float>(p.x()), static_cast<float>(p.y()),
                                               static_cast<float>(p.z()));
  }
  ::octomap::KeySet free_cells, occupied_cells;
  for (std::size_t k = 0; k < clouds.size(); ++k) {
    if (clouds[k].size() == 0) continue;
    const Vec3 o = scan.profile_poses[k].translation();
    tree.computeUpdate(clouds[k], ::octomap::point3d(static_cast<float>(o.x()), static_cast<float>(o.y()),
                                                     static_cast<float>(o.z())),
                       free_cells, occupied_cells, -1.0);
  }
  for (const auto& key : free_cells)
    if (occupied_cells.find(key) == occupied_cells.end()) tree.updateNode(key, false);
  for (const auto& key : occupied_cells) tree.updateNode(key, true);
}

}  // namespace nbs::octomap
