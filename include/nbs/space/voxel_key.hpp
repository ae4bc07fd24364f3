// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Integer voxel keys and the world ↔ key mapping of a voxel grid with edge length l_v.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>

#include "nbs/core/error.hpp"
#include "nbs/core/types.hpp"

namespace nbs {

/// Signed integer index of a voxel: voxel (x, y, z) covers [x·l_v, (x+1)·l_v) × ... in world metres.
/// Valid keys satisfy kMinIndex ≤ x, y, z ≤ kMaxIndex (21 bits per axis), so a key packs into 64 bits.
struct VoxelKey {
  std::int32_t x = 0;
  std::int32_t y = 0;
  std::int32_t z = 0;

  static constexpr int kBits = 21;                                     ///< bits per axis
  static constexpr std::int32_t kMinIndex = -(1 << (kBits - 1));       ///< −2^20
  static constexpr std::int32_t kMaxIndex = (1 << (kBits - 1)) - 1;    ///< 2^20 − 1

  [[nodiscard]] constexpr std::int32_t operator[](int axis) const { return axis == 0 ? x : (axis == 1 ? y : z); }
  [[nodiscard]] constexpr std::int32_t& operator[](int axis) { return axis == 0 ? x : (axis == 1 ? y : z); }
  [[nodiscard]] friend constexpr bool operator==(const VoxelKey&, const VoxelKey&) = default;

  /// True if every index is in [kMinIndex, kMaxIndex].
  [[nodiscard]] constexpr bool valid() const {
    return x >= kMinIndex && x <= kMaxIndex && y >= kMinIndex && y <= kMaxIndex && z >= kMinIndex &&
           z <= kMaxIndex;
  }
  /// 63-bit packing (21 bits per axis, offset 2^20). Precondition: valid(). Injective on valid keys.
  [[nodiscard]] constexpr std::uint64_t pack() const {
    constexpr std::uint64_t mask = (std::uint64_t{1} << kBits) - 1;
    const auto u = [](std::int32_t v) { return static_cast<std::uint64_t>(static_cast<std::int64_t>(v) - kMinIndex); };
    return (u(x) & mask) | ((u(y) & mask) << kBits) | ((u(z) & mask) << (2 * kBits));
  }
  /// Inverse of pack().
  [[nodiscard]] static constexpr VoxelKey unpack(std::uint64_t p) {
    constexpr std::uint64_t mask = (std::uint64_t{1} << kBits) - 1;
    const auto s = [](std::uint64_t v) { return static_cast<std::int32_t>(static_cast<std::int64_t>(v) + kMinIndex); };
    return {s(p & mask), s((p >> kBits) & mask), s((p >> (2 * kBits)) & mask)};
  }
};

/// Hash of a VoxelKey (a multiplicative mix of pack()); for std::unordered_* containers.
struct VoxelKeyHash {
  [[nodiscard]] std::size_t operator()(const VoxelKey& k) const noexcept {
    std::uint64_t h = k.pack() * 0x9E3779B97F4A7C15ull;
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};

/// Inclusive box of keys; empty when any min > max.
struct KeyBox {
  VoxelKey min{1, 1, 1};
  VoxelKey max{0, 0, 0};
  [[nodiscard]] bool empty() const { return min.x > max.x || min.y > max.y || min.z > max.z; }
  [[nodiscard]] bool contains(const VoxelKey& k) const {
    return k.x >= min.x && k.x <= max.x && k.y >= min.y && k.y <= max.y && k.z >= min.z && k.z <= max.z;
  }
  void extend(const VoxelKey& k) {
    if (empty()) {
      min = max = k;
      return;
    }
    for (int a = 0; a < 3; ++a) {
      if (k[a] < min[a]) min[a] = k[a];
      if (k[a] > max[a]) max[a] = k[a];
    }
  }
  /// Number of keys in the box (0 if empty).
  [[nodiscard]] std::uint64_t volume() const {
    if (empty()) return 0;
    std::uint64_t v = 1;
    for (int a = 0; a < 3; ++a) v *= static_cast<std::uint64_t>(static_cast<std::int64_t>(max[a]) - min[a] + 1);
    return v;
  }
};

/// World ↔ key mapping for edge length `resolution_m`: key = floor(coord · (1 / l_v)), computed exactly as OctoMap
/// does (multiplication by the reciprocal), so both classify a coordinate identically.
class VoxelGrid {
public:
  /// Throws InvalidArgument unless resolution_m is finite and > 0.
  explicit VoxelGrid(double resolution_m) : resolution_(resolution_m) {
    detail::require_positive("resolution_m", resolution_m);
    inverse_ = 1.0 / resolution_m;
  }

  [[nodiscard]] double resolution_m() const { return resolution_; }
  [[nodiscard]] double inverse_resolution() const { return inverse_; }

  /// Largest |coordinate| (metres) whose key is valid: the grid covers [−2^20·l_v, 2^20·l_v).
  [[nodiscard]] double half_extent_m() const { return static_cast<double>(-VoxelKey::kMinIndex) * resolution_; }

  /// Key of the voxel containing `p`; nullopt if `p` is not finite or outside the key range.
  [[nodiscard]] std::optional<VoxelKey> key_of(const Vec3& p) const {
    VoxelKey k;
    for (int a = 0; a < 3; ++a) {
      const double f = inverse_ * p[a];
      // floor(f) ∈ [kMinIndex, kMaxIndex] ⇔ kMinIndex ≤ f < kMaxIndex + 1; also rejects NaN.
      if (!(f >= VoxelKey::kMinIndex && f < VoxelKey::kMaxIndex + 1.0)) return std::nullopt;
      const auto t = static_cast<std::int32_t>(f);  // truncation; floor without a libm call
      k[a] = t - (static_cast<double>(t) > f ? 1 : 0);
    }
    return k;
  }

  /// True iff key_of(p) == k, for a valid k (false if p is not finite), without computing key_of(p): the same
  /// product inverse·p_a is compared with k_a ≤ · < k_a + 1 (⇔ floor = k_a).
  [[nodiscard]] bool in_voxel(const Vec3& p, const VoxelKey& k) const {
    bool in = true;
    for (int a = 0; a < 3; ++a) {
      const double f = inverse_ * p[a];
      const double lo = static_cast<double>(k[a]);
      in = in && f >= lo && f < lo + 1.0;
    }
    return in;
  }

  /// Centre of voxel `k` in world metres.
  [[nodiscard]] Vec3 center(const VoxelKey& k) const {
    return {(k.x + 0.5) * resolution_, (k.y + 0.5) * resolution_, (k.z + 0.5) * resolution_};
  }

  /// Keys of the voxels overlapping the world box `b` (clamped to the key range); empty if `b` is empty.
  [[nodiscard]] KeyBox key_box(const Aabb& b) const {
    KeyBox kb;
    if (b.empty()) return kb;
    for (int a = 0; a < 3; ++a) {
      const double lim = static_cast<double>(VoxelKey::kMaxIndex);
      kb.min[a] = static_cast<std::int32_t>(std::clamp(std::floor(inverse_ * b.min[a]), -lim - 1.0, lim));
      kb.max[a] = static_cast<std::int32_t>(std::clamp(std::floor(inverse_ * b.max[a]), -lim - 1.0, lim));
    }
    return kb;
  }

private:
  double resolution_;
  double inverse_ = 1.0;
};

}  // namespace nbs

template <>
struct std::hash<nbs::VoxelKey> : nbs::VoxelKeyHash {};
