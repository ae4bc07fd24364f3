// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Sparse per-voxel storage of the surface features of Sec. 4.5.1, kept apart from the voxel states so that only
/// surface voxels (occupied, p ≥ Parameters::occupied_threshold) pay for them. The mesh component computes the features; this only stores them.

#include <Eigen/Core>

#include <cmath>
#include <cstddef>
#include <unordered_map>

#include "nbs/core/error.hpp"
#include "nbs/space/voxel_key.hpp"

namespace nbs {

/// Surface features of one voxel i (Sec. 4.5.1).
struct SurfaceFeatures {
  float mean_density = 0.0f;                                ///< d̄_i ∈ [0, 1], Eq. 4.26
  Eigen::Vector3f mean_normal = Eigen::Vector3f::Zero();    ///< n̄_i, mean of unit vertex normals (|n̄_i| ≤ 1), Eq. 4.27
  float border_share = 0.0f;                                ///< b_i ∈ [0, 1], Eq. 4.28

  /// Throws InvalidArgument unless d̄_i, b_i ∈ [0, 1] and n̄_i is finite with |n̄_i| ≤ 1 (+1e-4).
  void validate() const {
    detail::require_in_range("mean_density", mean_density, 0.0, 1.0);
    detail::require_in_range("border_share", border_share, 0.0, 1.0);
    detail::require(mean_normal.allFinite() && mean_normal.norm() <= 1.0f + 1e-4f,
                    "mean_normal must be finite with norm <= 1, got (", mean_normal.transpose(), ")");
  }
};

/// Key → SurfaceFeatures. Not thread-safe for writes; concurrent const calls are safe.
class SurfaceFeatureMap {
public:
  /// Stores (overwrites) the features of voxel k. Throws InvalidArgument (map unchanged) if f is invalid.
  void set(const VoxelKey& k, const SurfaceFeatures& f) {
    f.validate();
    map_[k] = f;
  }
  /// Features of voxel k, or nullptr if none were stored.
  [[nodiscard]] const SurfaceFeatures* find(const VoxelKey& k) const {
    const auto it = map_.find(k);
    return it == map_.end() ? nullptr : &it->second;
  }
  /// Removes the features of k; returns true if there were any.
  bool erase(const VoxelKey& k) { return map_.erase(k) > 0; }
  void clear() { map_.clear(); }
  [[nodiscard]] std::size_t size() const { return map_.size(); }
  /// Calls f(key, features) for every stored entry, unspecified order.
  template <class F>
  void for_each(F&& f) const {
    for (const auto& [k, v] : map_) f(k, v);
  }
  [[nodiscard]] std::size_t memory_bytes() const {
    return map_.size() * (sizeof(VoxelKey) + sizeof(SurfaceFeatures) + 2 * sizeof(void*)) +
           map_.bucket_count() * sizeof(void*);
  }

private:
  std::unordered_map<VoxelKey, SurfaceFeatures, VoxelKeyHash> map_;
};

}  // namespace nbs
