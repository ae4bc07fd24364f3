// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// `octomap::OcTree` as a VoxelBackend (state: LogOddsState), adapted through `backend_traits` without wrapping.
///
/// Keys map one to one: OcTreeKey = VoxelKey + 2^15 per axis, so the tree stores keys in [−2^15, 2^15). Both use
/// key = floor(coord · (1/l_v)). Writes use `setNodeValue` (inner nodes updated, equal siblings pruned); a pruned
/// leaf reads as each of the voxels it covers. `make` widens the tree's clamping to log-odds ±13.8 so that the tree
/// stores what the update model computes (the model does its own clamping). Thread-safety: concurrent const calls are safe.

#include <octomap/OcTree.h>

#include <cstdint>
#include <optional>

#include "nbs/core/error.hpp"
#include "nbs/space/backend.hpp"
#include "nbs/space/log_odds_model.hpp"

namespace nbs {
namespace octomap {

inline constexpr std::int32_t kKeyOffset = 32768;  ///< octomap's tree_max_val for 16 levels

/// OcTreeKey of k, or nullopt if k is outside [−2^15, 2^15) on some axis.
[[nodiscard]] inline std::optional<::octomap::OcTreeKey> to_octree_key(const VoxelKey& k) {
  ::octomap::OcTreeKey o;
  for (int a = 0; a < 3; ++a) {
    const std::int32_t v = k[a] + kKeyOffset;
    if (v < 0 || v > 65535) return std::nullopt;
    o[a] = static_cast<::octomap::key_type>(v);
  }
  return o;
}
[[nodiscard]] inline VoxelKey from_octree_key(const ::octomap::OcTreeKey& o) {
  return {static_cast<std::int32_t>(o[0]) - kKeyOffset, static_cast<std::int32_t>(o[1]) - kKeyOffset,
          static_cast<std::int32_t>(o[2]) - kKeyOffset};
}

}  // namespace octomap

/// VoxelBackend adaptation of octomap::OcTree.
template <>
struct backend_traits<::octomap::OcTree> {
  using State = LogOddsState;
  using Tree = ::octomap::OcTree;
  [[nodiscard]] static Tree make(double resolution_m) {
    detail::require_positive("resolution_m", resolution_m);
    Tree t(resolution_m);
    t.setClampingThresMin(1e-6);  // store what the update model computes; the model clamps
    t.setClampingThresMax(1.0 - 1e-6);
    return t;
  }
  [[nodiscard]] static double resolution_m(const Tree& t) { return t.getResolution(); }
  [[nodiscard]] static State get(const Tree& t, const VoxelKey& k) {
    const auto o = octomap::to_octree_key(k);
    const auto* n = o ? t.search(*o) : nullptr;
    return n ? State{n->getLogOdds()} : State{};
  }
  [[nodiscard]] static bool observed(const Tree& t, const VoxelKey& k) {
    const auto o = octomap::to_octree_key(k);
    return o && t.search(*o) != nullptr;
  }
  /// Throws InvalidArgument if k is outside key_range().
  static void set(Tree& t, const VoxelKey& k, const State& s) {
    const auto o = octomap::to_octree_key(k);
    detail::require(o.has_value(), "octomap backend: key (", k.x, ", ", k.y, ", ", k.z, ") out of range");
    t.setNodeValue(*o, s.log_odds);
  }
  template <class F>
  static void for_each(const Tree& t, F&& f) {
    const unsigned depth = t.getTreeDepth();
    for (auto it = t.begin_leafs(), end = t.end_leafs(); it != end; ++it) {
      const VoxelKey base = octomap::from_octree_key(it.getIndexKey());
      const std::int32_t n = std::int32_t{1} << (depth - it.getDepth());
      const State s{it->getLogOdds()};
      for (std::int32_t z = 0; z < n; ++z)
        for (std::int32_t y = 0; y < n; ++y)
          for (std::int32_t x = 0; x < n; ++x) f(VoxelKey{base.x + x, base.y + y, base.z + z}, s);
    }
  }
  [[nodiscard]] static std::size_t size(const Tree& t) {
    std::size_t n = 0;
    for_each(t, [&n](const VoxelKey&, const State&) { ++n; });
    return n;
  }
  [[nodiscard]] static std::size_t memory_bytes(const Tree& t) { return t.memoryUsage(); }
  [[nodiscard]] static KeyBox observed_key_bounds(const Tree& t) {
    KeyBox b;
    for_each(t, [&b](const VoxelKey& k, const State&) { b.extend(k); });
    return b;
  }
  [[nodiscard]] static KeyBox key_range(const Tree&) {
    return {{-octomap::kKeyOffset, -octomap::kKeyOffset, -octomap::kKeyOffset},
            {octomap::kKeyOffset - 1, octomap::kKeyOffset - 1, octomap::kKeyOffset - 1}};
  }
};

static_assert(VoxelBackend<::octomap::OcTree>);

}  // namespace nbs
