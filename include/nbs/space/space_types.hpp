// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Value types shared by every voxel space (VoxelSpace, space/concepts.hpp): what integrating a scan did, a
/// planning ray and the outcome of casting it. World frame, metres.

#include <cstdint>

#include "nbs/core/types.hpp"
#include "nbs/space/voxel_key.hpp"

namespace nbs {

/// What `integrate` did with a scan. Counts add up: points = integrated + rejected_*.
struct IntegrationStats {
  std::uint64_t points = 0;                   ///< points in the scan(s)
  std::uint64_t integrated = 0;               ///< beams used
  std::uint64_t rejected_zero_length = 0;     ///< end point == sensor origin
  std::uint64_t rejected_outside_bounds = 0;  ///< end point outside the bounding box of the unknown area (clipped)
  std::uint64_t rejected_model = 0;           ///< the model refused the beam (e.g. σ(d) not finite and > 0)
  std::uint64_t voxel_updates = 0;            ///< voxel states changed
  std::uint64_t voxels_same_scan = 0;         ///< skipped: voxel already updated in this scan
  std::uint64_t voxels_similar_beam = 0;      ///< skipped: a similar beam was integrated there before (Sec. 3.3.2)

  IntegrationStats& operator+=(const IntegrationStats& o) {
    points += o.points;
    integrated += o.integrated;
    rejected_zero_length += o.rejected_zero_length;
    rejected_outside_bounds += o.rejected_outside_bounds;
    rejected_model += o.rejected_model;
    voxel_updates += o.voxel_updates;
    voxels_same_scan += o.voxels_same_scan;
    voxels_similar_beam += o.voxels_similar_beam;
    return *this;
  }
};

/// A planning ray from `origin` to `end`, world metres.
struct Ray {
  Vec3 origin = Vec3::Zero();
  Vec3 end = Vec3::Zero();
};

/// Outcome of one planning ray cast.
struct RaycastResult {
  bool hit = false;           ///< stopped at an occupied voxel
  VoxelKey hit_key{};         ///< that voxel (valid if hit)
  std::uint32_t voxels = 0;   ///< voxels visited (the callback was called this often)
};

}  // namespace nbs
