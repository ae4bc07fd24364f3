// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The collision model of workspace modeling (Sec. 5.5, Sec. 3.2.2): the voxels of a ProbabilisticVoxelSpace that a
/// motion planner must treat as obstacles, cleaned of free-floating groups and of inner voxels, and its closed
/// surface mesh. The OctoMap export is in nbs/octomap/collision_model_io.hpp.
///
/// Rules, in this order (the thesis: "all voxels with a probability p to be occupied below 25 % are removed",
/// "smaller groups of voxels which are free-floating in the air are erased as an obstacle always needs to be in
/// contact with the floor", "a data size-optimized model is created by removing inner voxels"):
///  1. probability: p < free_below → dropped; free_below ≤ p < occupied_from (unknown) → kept iff include_unknown;
///     voxels never observed inside the space's bounds are unknown (p = 0.5);
///  2. groups: connected components of the kept voxels (26-neighbourhood); a component none of whose voxels lies in
///     the floor layer (key z ≤ key z of floor_z_m, + 1) is removed if remove_floating; a component with fewer
///     than min_group_voxels voxels is removed;
///  3. inner voxels: a voxel whose 6 face neighbours all survived rule 2 is removed. Judged on the set after rule 2
///     and before any inner voxel is removed, so the surface of the obstacle set (its exposed faces) is unchanged.
/// Memory and time are proportional to the voxels that pass rule 1 (≈ 20 bytes each at the peak), plus, with
/// include_unknown, one block lookup per 8³ block of the bounds (never-observed blocks are not allocated).

#include <algorithm>
#include <array>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <memory>
#include <numeric>
#include <unordered_map>
#include <utility>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/mesh/indexed_mesh.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"

namespace nbs {

/// Setting of build_collision_model (probabilities of occupancy, world metres).
struct CollisionModelSetting {
  /// Voxels with p below this are free and dropped (Sec. 5.5: 0.25).
  double free_below = 0.25;
  /// Voxels with p ≥ this are occupied; free_below ≤ p < occupied_from is unknown.
  double occupied_from = 0.75;
  /// Keep unknown voxels (observed with free_below ≤ p < occupied_from, or never observed inside the bounds).
  /// Default true, as in the thesis's final model ("still contains all voxels which could not be freed"): a motion
  /// planner must not move through space that nobody has seen; it also keeps an object attached to the floor
  /// through unseen space (e.g. a table whose legs were never seen), which rule 2 would otherwise erase.
  bool include_unknown = true;
  /// Remove connected groups that do not touch the floor layer (thesis: an obstacle is always in contact with the
  /// floor). Default true.
  bool remove_floating = true;
  /// Height of the floor in the world frame (z up), metres. The floor layer is the voxel layer containing it and
  /// the one above (one voxel of tolerance for quantisation); lower voxels count as touching too.
  double floor_z_m = 0.0;
  /// Groups with fewer voxels are removed even if they touch the floor (speckle from noise). 0 = off (default: the
  /// thesis removes by floor contact only, and a small part standing on the floor is a real obstacle).
  std::uint64_t min_group_voxels = 0;
  /// Remove inner voxels (rule 3). Default true.
  bool remove_inner = true;
  /// Largest number of voxels passing rule 1; more → InvalidArgument before the groups are built (guards against
  /// include_unknown over a huge never-observed volume).
  std::uint64_t max_voxels = 50'000'000;

  /// Throws InvalidArgument naming the value unless 0 ≤ free_below ≤ occupied_from ≤ 1, floor_z_m is finite and
  /// max_voxels is in [1, 2^32).
  void validate() const {
    detail::require_in_range("CollisionModelSetting::free_below", free_below, 0.0, 1.0);
    detail::require_in_range("CollisionModelSetting::occupied_from", occupied_from, free_below, 1.0);
    detail::require(std::isfinite(floor_z_m), "CollisionModelSetting::floor_z_m must be finite, got ", floor_z_m);
    detail::require(max_voxels >= 1 && max_voxels < (std::uint64_t{1} << 32),
                    "CollisionModelSetting::max_voxels must be in [1, 2^32), got ", max_voxels);
  }
};

/// What each rule did (voxel counts).
struct CollisionModelCounts {
  std::uint64_t candidates = 0;        ///< voxels passing rule 1
  std::uint64_t dropped_free = 0;      ///< observed voxels with p < free_below
  std::uint64_t dropped_unknown = 0;   ///< observed unknown voxels dropped because include_unknown is off
  std::uint64_t removed_floating = 0;  ///< voxels of groups without floor contact
  std::uint64_t removed_small = 0;     ///< voxels of floor-touching groups below min_group_voxels
  std::uint64_t removed_inner = 0;     ///< inner voxels (rule 3)
  std::uint64_t groups_kept = 0;       ///< connected groups kept (0 if rule 2 is off: groups are not built)
  std::uint64_t groups_removed = 0;    ///< connected groups removed by rule 2
};

/// Face bits of CollisionModel::exposed_faces: bit 2·axis is the −axis face, bit 2·axis + 1 the +axis face.
inline constexpr std::uint8_t kAllFaces = 0x3F;

/// The obstacle voxels for a motion planner. Invariants: voxels sorted by (z, y, x) without duplicates;
/// exposed_faces[i] holds the faces of voxels[i] whose neighbour is not an obstacle voxel (nonzero for every voxel
/// if inner voxels were removed); voxels.size() = candidates − removed_floating − removed_small − removed_inner.
struct CollisionModel {
  double resolution_m = 0.0;                ///< voxel edge l_v, metres; voxel k covers [k·l_v, (k+1)·l_v)
  std::vector<VoxelKey> voxels;             ///< the obstacle voxels kept
  std::vector<std::uint8_t> exposed_faces;  ///< one face mask per voxel (kAllFaces layout)
  CollisionModelCounts counts;

  [[nodiscard]] std::size_t size() const { return voxels.size(); }
  [[nodiscard]] bool empty() const { return voxels.empty(); }
  /// Centre of voxel i, world metres.
  [[nodiscard]] Vec3 center(std::size_t i) const {
    const VoxelKey& k = voxels[i];
    return {(k.x + 0.5) * resolution_m, (k.y + 0.5) * resolution_m, (k.z + 0.5) * resolution_m};
  }
};

namespace detail {

/// Calls f(i, j) for every pair of sorted packed keys with keys[j] the neighbour of keys[i] at offset d (a valid
/// key). Packing is linear for valid keys, so pack(k + d) = pack(k) + Δ: one merge sweep, O(n).
template <class F>
void for_each_neighbour_pair(const std::vector<std::uint64_t>& keys, const VoxelKey& d, F&& f) {
  const std::int64_t delta = std::int64_t{d.x} + (std::int64_t{d.y} << VoxelKey::kBits) +
                             (std::int64_t{d.z} << (2 * VoxelKey::kBits));
  std::size_t j = 0;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const VoxelKey k = VoxelKey::unpack(keys[i]);
    if (!VoxelKey{k.x + d.x, k.y + d.y, k.z + d.z}.valid()) continue;
    const auto target = static_cast<std::uint64_t>(static_cast<std::int64_t>(keys[i]) + delta);
    while (j < keys.size() && keys[j] < target) ++j;
    if (j == keys.size()) return;
    if (keys[j] == target) f(i, j);
  }
}

[[nodiscard]] inline std::uint32_t find_root(std::vector<std::uint32_t>& parent, std::uint32_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];  // path halving
    i = parent[i];
  }
  return i;
}

/// A BlockBackend whose blocks tell which voxels were ever observed (the fast path of collect_unobserved). A concept
/// of its own: a requires-expression naming B::Block inline in `if constexpr` is a hard error for clang before 16
/// when B has no Block.
template <class B>
concept ObservedBlocks = BlockBackend<B> && requires(const typename B::Block& b, int i) {
  { b.is_observed(i) } -> std::convertible_to<bool>;
};

/// Appends the packed keys of the never-observed voxels of `space` inside kb to `out` (at most `limit` in all).
template <class B, class M>
void collect_unobserved(const ProbabilisticVoxelSpace<B, M>& space, const KeyBox& kb, std::vector<std::uint64_t>& out,
                        std::uint64_t limit) {
  const auto push = [&](const VoxelKey& k) {
    require(out.size() < limit, "build_collision_model: more than max_voxels = ", limit,
            " obstacle voxels (unknown ones included); raise max_voxels or set include_unknown = false");
    out.push_back(k.pack());
  };
  if constexpr (ObservedBlocks<B>) {
    // Block by block: a block never allocated holds only unknown voxels, an allocated one is read once.
    constexpr int e = B::kEdgeBits;
    typename B::template BasicReader<0> reader(space.backend());
    for (std::int32_t bz = kb.min.z >> e; bz <= kb.max.z >> e; ++bz)
      for (std::int32_t by = kb.min.y >> e; by <= kb.max.y >> e; ++by)
        for (std::int32_t bx = kb.min.x >> e; bx <= kb.max.x >> e; ++bx) {
          const VoxelKey o{bx * B::kEdge, by * B::kEdge, bz * B::kEdge};
          const auto* blk = reader.find(B::block_id(o));
          for (std::int32_t z = std::max(o.z, kb.min.z); z <= std::min(o.z + B::kEdge - 1, kb.max.z); ++z)
            for (std::int32_t y = std::max(o.y, kb.min.y); y <= std::min(o.y + B::kEdge - 1, kb.max.y); ++y)
              for (std::int32_t x = std::max(o.x, kb.min.x); x <= std::min(o.x + B::kEdge - 1, kb.max.x); ++x) {
                const VoxelKey k{x, y, z};
                if (blk == nullptr || !blk->is_observed(B::local_index(k))) push(k);
              }
        }
  } else {
    for (std::int32_t z = kb.min.z; z <= kb.max.z; ++z)
      for (std::int32_t y = kb.min.y; y <= kb.max.y; ++y)
        for (std::int32_t x = kb.min.x; x <= kb.max.x; ++x)
          if (!space.observed(VoxelKey{x, y, z})) push(VoxelKey{x, y, z});
  }
}

}  // namespace detail

/// Builds the collision model of `space` (rules in the file comment). Throws InvalidArgument (setting.validate(),
/// or more than setting.max_voxels voxels passing rule 1); FileError if a flushed block cannot be read. Const on
/// the space; safe to run concurrently with other const calls.
template <class B, class M>
[[nodiscard]] CollisionModel build_collision_model(const ProbabilisticVoxelSpace<B, M>& space,
                                                   const CollisionModelSetting& setting = {}) {
  setting.validate();
  CollisionModel out;
  out.resolution_m = space.resolution_m();
  CollisionModelCounts& c = out.counts;

  // Rule 1 on the observed voxels, then the never-observed ones of the bounds.
  std::vector<std::uint64_t> keys;
  space.for_each([&](const VoxelKey& k, const auto& s) {
    const double p = space.model().probability(s);
    if (p < setting.free_below) {
      ++c.dropped_free;
    } else if (p < setting.occupied_from && !setting.include_unknown) {
      ++c.dropped_unknown;
    } else {
      detail::require(keys.size() < setting.max_voxels, "build_collision_model: more than max_voxels = ",
                      setting.max_voxels, " obstacle voxels");
      keys.push_back(k.pack());
    }
  });
  const double p_unobserved = space.model().probability(typename M::State{});  // 0.5
  if (p_unobserved >= setting.free_below && (setting.include_unknown || p_unobserved >= setting.occupied_from))
    detail::collect_unobserved(space, space.bounds_keys(), keys, setting.max_voxels);
  std::sort(keys.begin(), keys.end());  // (z, y, x) order: packing puts z in the high bits
  c.candidates = keys.size();
  const auto n = static_cast<std::uint32_t>(keys.size());

  // Rule 2: union-find over the 13 forward offsets of the 26-neighbourhood.
  if (setting.remove_floating || setting.min_group_voxels > 0) {
    std::vector<std::uint32_t> parent(n);
    std::iota(parent.begin(), parent.end(), 0u);
    for (int dz = 0; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          if (dz == 0 && (dy < 0 || (dy == 0 && dx <= 0))) continue;  // backward offsets and (0, 0, 0)
          detail::for_each_neighbour_pair(keys, VoxelKey{dx, dy, dz}, [&](std::size_t i, std::size_t j) {
            const std::uint32_t a = detail::find_root(parent, static_cast<std::uint32_t>(i));
            const std::uint32_t b = detail::find_root(parent, static_cast<std::uint32_t>(j));
            if (a != b) parent[std::max(a, b)] = std::min(a, b);
          });
        }
    const double floor_key = std::floor(setting.floor_z_m * space.grid().inverse_resolution());  // as key_of
    std::vector<std::uint32_t> group_size(n, 0);
    std::vector<std::uint8_t> on_floor(n, 0);
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint32_t r = detail::find_root(parent, i);
      ++group_size[r];
      if (static_cast<double>(VoxelKey::unpack(keys[i]).z) <= floor_key + 1.0) on_floor[r] = 1;
    }
    // Roots are the smallest index of their group (union keeps the smaller), so compaction in place is safe.
    std::size_t kept = 0;
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint32_t r = detail::find_root(parent, i);
      const bool floating = setting.remove_floating && on_floor[r] == 0;
      const bool small = !floating && group_size[r] < setting.min_group_voxels;
      if (r == i) ++(floating || small ? c.groups_removed : c.groups_kept);
      if (floating) {
        ++c.removed_floating;
      } else if (small) {
        ++c.removed_small;
      } else {
        keys[kept++] = keys[i];
      }
    }
    keys.resize(kept);
  }

  // Rule 3 and exposed faces: face neighbours among the voxels after rule 2.
  std::vector<std::uint8_t> neighbours(keys.size(), 0);
  for (int a = 0; a < 3; ++a) {
    VoxelKey d{0, 0, 0};
    d[a] = 1;
    detail::for_each_neighbour_pair(keys, d, [&](std::size_t i, std::size_t j) {
      neighbours[i] |= static_cast<std::uint8_t>(1u << (2 * a + 1));  // i has a +a neighbour
      neighbours[j] |= static_cast<std::uint8_t>(1u << (2 * a));      // j has a −a neighbour
    });
  }
  out.voxels.reserve(keys.size());
  out.exposed_faces.reserve(keys.size());
  for (std::size_t i = 0; i < keys.size(); ++i) {
    if (setting.remove_inner && neighbours[i] == kAllFaces) {
      ++c.removed_inner;
      continue;
    }
    out.voxels.push_back(VoxelKey::unpack(keys[i]));
    out.exposed_faces.push_back(static_cast<std::uint8_t>(~neighbours[i] & kAllFaces));
  }
  return out;
}

/// The surface of the model's obstacle voxels: one quad (two triangles) per exposed face, vertices shared (voxel
/// corners, world metres), counter-clockwise seen from outside. The surface is that of the whole obstacle set
/// (inner voxels have no exposed face), hence closed: every edge is used by two triangles, or by four where two
/// voxels meet only along that edge (still consistently oriented). Quad of face (axis a, sign ±) with u = a+1,
/// v = a+2 (mod 3): corners c, c+e_u, c+e_u+e_v, c+e_v, reversed for the − face; split along c – c+e_u+e_v.
[[nodiscard]] inline IndexedMesh collision_mesh(const CollisionModel& model) {
  detail::require(model.exposed_faces.size() == model.voxels.size(), "collision_mesh: ", model.exposed_faces.size(),
                  " face masks for ", model.voxels.size(), " voxels");
  detail::require_positive("collision_mesh: resolution_m", model.resolution_m);
  IndexedMesh mesh;
  std::unordered_map<VoxelKey, std::uint32_t, VoxelKeyHash> index;  // corner key → vertex
  const auto vertex = [&](const VoxelKey& k) {
    const auto [it, fresh] = index.try_emplace(k, static_cast<std::uint32_t>(mesh.vertices.size()));
    if (fresh)
      mesh.vertices.emplace_back(k.x * model.resolution_m, k.y * model.resolution_m, k.z * model.resolution_m);
    return it->second;
  };
  for (std::size_t i = 0; i < model.voxels.size(); ++i) {
    for (int f = 0; f < 6; ++f) {
      if (((model.exposed_faces[i] >> f) & 1u) == 0) continue;
      const int a = f / 2, u = (a + 1) % 3, v = (a + 2) % 3;
      const bool plus = (f & 1) != 0;
      VoxelKey q[4] = {model.voxels[i], model.voxels[i], model.voxels[i], model.voxels[i]};
      for (auto& k : q) k[a] += plus ? 1 : 0;
      q[1][u] += 1;
      q[2][u] += 1;
      q[2][v] += 1;
      q[3][v] += 1;
      if (!plus) std::swap(q[1], q[3]);
      const std::uint32_t w[4] = {vertex(q[0]), vertex(q[1]), vertex(q[2]), vertex(q[3])};
      mesh.triangles.push_back({w[0], w[1], w[2]});
      mesh.triangles.push_back({w[0], w[2], w[3]});
    }
  }
  return mesh;
}

}  // namespace nbs
