// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// A small open-addressing hash set of packed voxel keys, cleared in O(1) by a generation stamp, so one set is
/// reused across the candidates a thread evaluates (the per-candidate visited marking of Sec. 4.5.3).

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace nbs::detail {

/// Not thread-safe; one per thread.
class KeySet {
public:
  explicit KeySet(std::size_t capacity_hint = 1u << 12) { allocate(round_up(capacity_hint * 2)); }

  /// Forgets every key (O(1) except once every 2^32 − 1 clears).
  void clear() {
    size_ = 0;
    if (++generation_ == 0) {
      std::fill(stamps_.begin(), stamps_.end(), 0u);
      generation_ = 1;
    }
  }
  /// Inserts `key`; returns true if it was not in the set.
  bool insert(std::uint64_t key) {
    if (2 * (size_ + 1) > keys_.size()) grow();
    return insert_no_grow(key);
  }
  [[nodiscard]] bool contains(std::uint64_t key) const {
    for (std::size_t i = slot(key);; i = (i + 1) & mask_) {
      if (stamps_[i] != generation_) return false;
      if (keys_[i] == key) return true;
    }
  }
  [[nodiscard]] std::size_t size() const { return size_; }

private:
  static std::size_t round_up(std::size_t n) {
    std::size_t c = 16;
    while (c < n) c *= 2;
    return c;
  }
  void allocate(std::size_t cap) {
    keys_.assign(cap, 0);
    stamps_.assign(cap, 0u);
    mask_ = cap - 1;
    generation_ = 1;
    size_ = 0;
  }
  [[nodiscard]] std::size_t slot(std::uint64_t key) const {
    std::uint64_t h = key * 0x9E3779B97F4A7C15ull;
    return static_cast<std::size_t>(h ^ (h >> 32)) & mask_;
  }
  bool insert_no_grow(std::uint64_t key) {
    for (std::size_t i = slot(key);; i = (i + 1) & mask_) {
      if (stamps_[i] != generation_) {
        stamps_[i] = generation_;
        keys_[i] = key;
        ++size_;
        return true;
      }
      if (keys_[i] == key) return false;
    }
  }
  void grow() {
    std::vector<std::uint64_t> old;
    old.reserve(size_);
    for (std::size_t i = 0; i < keys_.size(); ++i)
      if (stamps_[i] == generation_) old.push_back(keys_[i]);
    allocate(keys_.size() * 2);
    for (std::uint64_t k : old) insert_no_grow(k);
  }

  std::vector<std::uint64_t> keys_;
  std::vector<std::uint32_t> stamps_;
  std::size_t mask_ = 0;
  std::size_t size_ = 0;
  std::uint32_t generation_ = 1;
};

}  // namespace nbs::detail
