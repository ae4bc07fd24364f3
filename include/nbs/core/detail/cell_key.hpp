// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Integer grid cells packed into one 64-bit key (21 bits per axis) and a flat open-addressing map from such keys to
/// 32-bit values: the one packing shared by the mesh's spatial hash, the scan normals, the ICP's model grid and the
/// viewer's decimation.

#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <optional>
#include <string_view>
#include <utility>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/core/types.hpp"

namespace nbs::detail {

/// Cells that pack: every coordinate in [kMinCellIndex, kMaxCellIndex] = [−2²⁰, 2²⁰ − 1].
inline constexpr int kMinCellIndex = -(1 << 20);
inline constexpr int kMaxCellIndex = (1 << 20) - 1;

/// True if every coordinate of `c` is in [kMinCellIndex, kMaxCellIndex].
[[nodiscard]] inline bool cell_in_key_range(const Eigen::Vector3i& c) noexcept {
  return c.x() >= kMinCellIndex && c.x() <= kMaxCellIndex && c.y() >= kMinCellIndex && c.y() <= kMaxCellIndex &&
         c.z() >= kMinCellIndex && c.z() <= kMaxCellIndex;
}

/// Key of cell `c`: each coordinate + 2²⁰ in 21 bits, x highest, so keys grow with (x, y, z) in lexicographic
/// order. Precondition: cell_in_key_range(c) (the caller has clamped or checked; else see pack_cell_key_checked).
[[nodiscard]] inline std::uint64_t pack_cell_key(const Eigen::Vector3i& c) noexcept {
  constexpr std::uint64_t mask = (std::uint64_t{1} << 21) - 1;
  return ((static_cast<std::uint64_t>(c.x() - kMinCellIndex) & mask) << 42) |
         ((static_cast<std::uint64_t>(c.y() - kMinCellIndex) & mask) << 21) |
         (static_cast<std::uint64_t>(c.z() - kMinCellIndex) & mask);
}

/// The cell of a key made by pack_cell_key.
[[nodiscard]] inline Eigen::Vector3i unpack_cell_key(std::uint64_t key) noexcept {
  constexpr std::uint64_t mask = (std::uint64_t{1} << 21) - 1;
  return {static_cast<int>((key >> 42) & mask) + kMinCellIndex, static_cast<int>((key >> 21) & mask) + kMinCellIndex,
          static_cast<int>(key & mask) + kMinCellIndex};
}

/// The cell ⌊scaled⌋ (per axis) if it packs, else nullopt (also for NaN or infinite coordinates).
[[nodiscard]] inline std::optional<Eigen::Vector3i> cell_index(const Vec3& scaled) noexcept {
  const Vec3 f = scaled.array().floor();
  // Per coefficient (a NaN fails both comparisons; minCoeff/maxCoeff may skip it).
  if (!((f.array() >= kMinCellIndex).all() && (f.array() <= kMaxCellIndex).all())) return std::nullopt;
  return Eigen::Vector3i(f.cast<int>());
}

/// Key of the cell ⌊scaled⌋; throws InvalidArgument naming `what` and the coordinates if that cell does not pack
/// (|coordinate| beyond 2²⁰ cells, NaN or infinite).
[[nodiscard]] inline std::uint64_t pack_cell_key_checked(const Vec3& scaled, std::string_view what) {
  const std::optional<Eigen::Vector3i> c = cell_index(scaled);
  require(c.has_value(), what, ": cell coordinates (", scaled.x(), ", ", scaled.y(), ", ", scaled.z(),
          ") are outside the packable range [", kMinCellIndex, ", ", kMaxCellIndex + 1, ") per axis");
  return pack_cell_key(*c);
}

/// The splitmix64 finaliser of a key: every key bit reaches the low bits a power-of-two table uses.
[[nodiscard]] constexpr std::uint64_t mix_cell_key(std::uint64_t h) noexcept {
  h = (h ^ (h >> 30)) * 0xBF58476D1CE4E5B9ull;
  h = (h ^ (h >> 27)) * 0x94D049BB133111EBull;
  return h ^ (h >> 31);
}

/// Flat open-addressing map (linear probing, load ≤ 1/2) from packed cell keys to 32-bit values. Insert only.
/// Not thread-safe for writes; const lookups may run concurrently.
class CellKeyMap {
public:
  static constexpr std::uint32_t kNone = ~std::uint32_t{0};

  explicit CellKeyMap(std::size_t expected = 16) { rehash(capacity_for(expected)); }

  [[nodiscard]] std::size_t size() const { return used_; }

  /// The value of `key`, or kNone.
  [[nodiscard]] std::uint32_t find(std::uint64_t key) const {
    const Slot& s = slots_[slot_of(key)];
    return s.key == kEmpty ? kNone : s.value;
  }

  /// Inserts `key` → `value` unless present. Returns the stored value and whether it was inserted.
  std::pair<std::uint32_t, bool> try_emplace(std::uint64_t key, std::uint32_t value) {
    std::size_t i = slot_of(key);
    if (slots_[i].key != kEmpty) return {slots_[i].value, false};
    if (2 * (used_ + 1) > slots_.size()) {
      rehash(slots_.size() * 2);
      i = slot_of(key);
    }
    slots_[i] = {key, value};
    ++used_;
    return {value, true};
  }

  /// Heap bytes of the table.
  [[nodiscard]] std::size_t memory_bytes() const { return slots_.capacity() * sizeof(Slot); }

private:
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};  // no packed key has all 64 bits set
  struct Slot {
    std::uint64_t key = kEmpty;
    std::uint32_t value = 0;
  };
  [[nodiscard]] static std::size_t capacity_for(std::size_t n) {
    std::size_t c = 16;
    while (c < 2 * n) c *= 2;
    return c;
  }
  [[nodiscard]] std::size_t slot_of(std::uint64_t key) const {
    const std::size_t m = slots_.size() - 1;
    std::size_t s = static_cast<std::size_t>(mix_cell_key(key)) & m;
    while (slots_[s].key != kEmpty && slots_[s].key != key) s = (s + 1) & m;
    return s;
  }
  void rehash(std::size_t capacity) {
    std::vector<Slot> old(capacity);
    old.swap(slots_);
    for (const Slot& o : old)
      if (o.key != kEmpty) slots_[slot_of(o.key)] = o;
  }

  std::vector<Slot> slots_;
  std::size_t used_ = 0;
};

}  // namespace nbs::detail
