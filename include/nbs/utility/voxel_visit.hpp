// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// What a utility term sees of one simulated beam (Sec. 4.5.3): one `VoxelVisit` per voxel the planning ray
/// crosses, in order from the sensor, then one `RayEnd`.

#include <cstdint>

#include "nbs/core/types.hpp"
#include "nbs/space/surface_features.hpp"
#include "nbs/space/voxel_key.hpp"
#include "nbs/utility/utility_function.hpp"

namespace nbs {

/// One voxel crossed by a simulated beam of a scan candidate.
struct VoxelVisit {
  VoxelKey key{};                              ///< the voxel
  double probability = 0.5;                    ///< occupancy p_i ∈ [0, 1] (0.5 if unknown)
  bool observed = false;                       ///< the voxel was ever updated by a scan
  bool occupied = false;                       ///< the space's model calls it occupied (the ray stops here)
  /// True the first time this voxel is met while evaluating the current candidate. Terms that follow Sec. 4.5.3
  /// ("voxels already considered … are marked as visited") count a voxel only when this is true.
  bool first_visit = true;
  const SurfaceFeatures* features = nullptr;   ///< d̄_i, n̄_i, b_i (Sec. 4.5.1) if stored, else nullptr
  Vec3 direction = Vec3::UnitZ();              ///< unit ray direction, world frame
  double distance_m = 0.0;                     ///< distance from the ray origin to the voxel centre, metres
  std::uint32_t index = 0;                     ///< position along the ray: 0 for the first voxel visited
  /// voxel_entropy(probability) in bits if the evaluator precomputed it (it does), else negative. Read it with
  /// entropy(); a driver that changes `probability` must leave this negative.
  double entropy_bits = -1.0;

  /// H(p_i) in bits (the summand of Eq. 4.32): the precomputed value if set, else voxel_entropy(probability).
  [[nodiscard]] double entropy() const { return entropy_bits >= 0.0 ? entropy_bits : voxel_entropy(probability); }
};

/// How a simulated beam ended.
struct RayEnd {
  bool hit = false;             ///< stopped at an occupied voxel (the last VoxelVisit)
  std::uint32_t voxels = 0;     ///< voxels visited on this ray
  /// ended at an obstacle outside the space (cut by EvaluationSetting::occluder, no occupied voxel before the cut)
  bool occluded = false;
};

}  // namespace nbs
