// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// UnknownAreaGrid: the voxel grid of a space together with the bounding box of the unknown area (Sec. 4.1) it is
/// restricted to, clipped to the keys the storage can hold. Written once for every VoxelSpace model
/// (ProbabilisticVoxelSpace holds one; a user-written space can hold one too).

#include "nbs/core/error.hpp"
#include "nbs/core/types.hpp"
#include "nbs/space/voxel_key.hpp"

namespace nbs {

/// Grid of edge l_v plus the unknown-area box in world metres. Invariants: bounds() ⊆ the key range's box,
/// voxel_bounds() is the union of the voxels overlapping bounds() shrunk by 10⁻⁶ l_v, bounds_keys() their keys.
class UnknownAreaGrid {
public:
  /// Every valid key (21 bits per axis).
  [[nodiscard]] static KeyBox full_key_range() {
    return {{VoxelKey::kMinIndex, VoxelKey::kMinIndex, VoxelKey::kMinIndex},
            {VoxelKey::kMaxIndex, VoxelKey::kMaxIndex, VoxelKey::kMaxIndex}};
  }

  /// Grid of edge `resolution_m` over `unknown_area` (empty box = the whole key range `keys`). Throws
  /// InvalidArgument if resolution_m ≤ 0 or not finite, or unknown_area is not finite or does not fit inside the
  /// key range at this resolution (keys·l_v: ±2^20 voxels for HashedBlockBackend, ±1.05 mm at 1 nm; it is never
  /// clipped silently).
  explicit UnknownAreaGrid(double resolution_m, const Aabb& unknown_area = {}, const KeyBox& keys = full_key_range())
      : grid_(resolution_m) {
    Aabb range;
    const double eps = 1e-6 * resolution_m;
    for (int a = 0; a < 3; ++a) {
      range.min[a] = keys.min[a] * resolution_m;
      range.max[a] = (keys.max[a] + 1.0) * resolution_m - eps;
    }
    if (unknown_area.empty()) {
      bounds_ = range;
    } else {
      detail::require(unknown_area.min.allFinite() && unknown_area.max.allFinite(),
                      "unknown_area must be finite, got min (", unknown_area.min.transpose(), ") max (",
                      unknown_area.max.transpose(), ")");
      detail::require((unknown_area.min.array() >= range.min.array()).all() &&
                          (unknown_area.max.array() <= range.max.array()).all(),
                      "unknown_area min (", unknown_area.min.transpose(), ") max (", unknown_area.max.transpose(),
                      ") m does not fit the key range at voxel size ", resolution_m, " m: min (",
                      range.min.transpose(), ") max (", range.max.transpose(), ") m");
      bounds_ = unknown_area;
    }
    keys_ = grid_.key_box(bounds_);
    for (int a = 0; a < 3; ++a) {
      voxel_bounds_.min[a] = keys_.min[a] * resolution_m + eps;
      voxel_bounds_.max[a] = (keys_.max[a] + 1.0) * resolution_m - eps;
    }
  }

  [[nodiscard]] const VoxelGrid& grid() const { return grid_; }
  [[nodiscard]] double resolution_m() const { return grid_.resolution_m(); }
  /// The bounding box of the unknown area actually used (clipped to the key range), world metres.
  [[nodiscard]] const Aabb& bounds() const { return bounds_; }
  /// The union of the voxels overlapping bounds() (shrunk by 10⁻⁶ l_v): beams and rays are clipped to it.
  [[nodiscard]] const Aabb& voxel_bounds() const { return voxel_bounds_; }
  /// Keys of the voxels overlapping bounds().
  [[nodiscard]] const KeyBox& bounds_keys() const { return keys_; }

private:
  VoxelGrid grid_;
  Aabb bounds_;
  Aabb voxel_bounds_;
  KeyBox keys_;
};

}  // namespace nbs
