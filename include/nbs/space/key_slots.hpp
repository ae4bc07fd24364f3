// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// KeySlots: voxel key → small integer slot, for per-call accumulation over a bounded set of voxels. Dense (one
/// int32 per voxel of a key box) when the box has at most `dense_limit` voxels, else hashed. Not thread-safe.

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "nbs/space/voxel_key.hpp"

namespace nbs {

class KeySlots {
public:
  static constexpr std::int32_t kNone = -1;
  static constexpr std::size_t kDefaultDenseLimit = std::size_t{1} << 22;  ///< 16 MiB of slots

  /// Slots for keys inside `box` (keys outside are never stored: find() gives kNone, assign() is ignored).
  explicit KeySlots(const KeyBox& box, std::size_t dense_limit = kDefaultDenseLimit) : box_(box) {
    if (box.empty()) return;
    nx_ = static_cast<std::size_t>(std::int64_t{box.max.x} - box.min.x + 1);
    ny_ = static_cast<std::size_t>(std::int64_t{box.max.y} - box.min.y + 1);
    const auto nz = static_cast<std::size_t>(std::int64_t{box.max.z} - box.min.z + 1);
    // Overflow-safe: each extent is < 2^21, so nx·ny < 2^42 and the last product is checked by division.
    const std::size_t nxy = nx_ * ny_;
    dense_ = nxy <= dense_limit && nz <= dense_limit / nxy;
    if (dense_) slots_.assign(nxy * nz, kNone);
  }

  [[nodiscard]] bool dense() const { return dense_; }

  /// Slot of `k`, kNone if it has none.
  [[nodiscard]] std::int32_t find(const VoxelKey& k) const {
    if (!box_.contains(k)) return kNone;
    if (dense_) return slots_[index(k)];
    const auto it = map_.find(k);
    return it == map_.end() ? kNone : it->second;
  }
  /// Sets the slot of `k` (ignored outside the box).
  void assign(const VoxelKey& k, std::int32_t slot) {
    if (!box_.contains(k)) return;
    if (dense_) slots_[index(k)] = slot;
    else map_[k] = slot;
  }

private:
  [[nodiscard]] std::size_t index(const VoxelKey& k) const {
    return (static_cast<std::size_t>(k.z - box_.min.z) * ny_ + static_cast<std::size_t>(k.y - box_.min.y)) * nx_ +
           static_cast<std::size_t>(k.x - box_.min.x);
  }

  KeyBox box_;
  std::size_t nx_ = 0, ny_ = 0;
  bool dense_ = false;
  std::vector<std::int32_t> slots_;
  std::unordered_map<VoxelKey, std::int32_t, VoxelKeyHash> map_;
};

}  // namespace nbs
