// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Cuts of the key space into slabs of whole blocks along one axis, balanced by the voxels of a set of walks: the
/// work split of ProbabilisticVoxelSpace::integrate(scan, threads).

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "nbs/space/voxel_key.hpp"

namespace nbs::detail {

/// The keys with key[axis] in [lo, hi) (every key by default).
struct KeySlab {
  int axis = 0;
  std::int32_t lo = VoxelKey::kMinIndex;
  std::int32_t hi = VoxelKey::kMaxIndex + 1;
  [[nodiscard]] bool owns(const VoxelKey& k) const { return k[axis] >= lo && k[axis] < hi; }
};

/// A walk from `first` to `last` (voxel keys) whose cost `weight` is spread evenly over its keys along each axis.
struct WeightedWalk {
  VoxelKey first, last;
  double weight;
};

/// At most `slabs` slabs that partition the key space along one axis, cut at multiples of 2^edge_bits (block faces),
/// over the walks keys_of(k) → std::optional<WeightedWalk> (nullopt: no walk), k = 0 … count − 1. Per axis the load of
/// a block is the weight its walks' keys along that axis carry; the cuts fall where the running load first reaches
/// t/slabs of the total (t = 1 … slabs − 1); the axis whose heaviest slab is lightest wins (ties: the lower axis). One
/// slab if there is no walk, slabs ≤ 1, or the walks lie in one block along every axis; fewer than `slabs` where
/// the walks span fewer blocks.
template <class KeysOf>
[[nodiscard]] std::vector<KeySlab> balance_slabs(std::size_t count, KeysOf&& keys_of, unsigned slabs, int edge_bits) {
  std::vector<KeySlab> best(1);
  if (slabs <= 1) return best;
  std::int32_t lo[3], hi[3];  // block range of the walks per axis
  for (int a = 0; a < 3; ++a) lo[a] = std::numeric_limits<std::int32_t>::max(), hi[a] = std::numeric_limits<std::int32_t>::min();
  for (std::size_t i = 0; i < count; ++i) {
    const auto w = keys_of(i);
    if (!w) continue;
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min({lo[a], w->first[a] >> edge_bits, w->last[a] >> edge_bits});
      hi[a] = std::max({hi[a], w->first[a] >> edge_bits, w->last[a] >> edge_bits});
    }
  }
  if (lo[0] > hi[0]) return best;  // no walk
  const std::int32_t edge = std::int32_t{1} << edge_bits;
  double best_load = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    const std::size_t blocks = static_cast<std::size_t>(hi[a] - lo[a]) + 1;
    std::vector<double> point(blocks, 0.0), range(blocks + 1, 0.0);  // load per block: point + running sum of range
    const auto at = [&](std::int32_t b) { return static_cast<std::size_t>(b - lo[a]); };
    for (std::size_t i = 0; i < count; ++i) {
      const auto w = keys_of(i);
      if (!w) continue;
      const std::int32_t k0 = std::min(w->first[a], w->last[a]), k1 = std::max(w->first[a], w->last[a]);
      const double per_key = w->weight / static_cast<double>(k1 - k0 + 1);
      const std::int32_t b0 = k0 >> edge_bits, b1 = k1 >> edge_bits;
      if (b0 == b1) {
        point[at(b0)] += per_key * (k1 - k0 + 1);
        continue;
      }
      point[at(b0)] += per_key * ((b0 + 1) * edge - k0);
      point[at(b1)] += per_key * (k1 - b1 * edge + 1);
      range[at(b0) + 1] += per_key * edge;  // the blocks strictly between b0 and b1
      range[at(b1)] -= per_key * edge;
    }
    std::vector<double> load(blocks);
    double total = 0.0, run = 0.0;
    for (std::size_t i = 0; i < blocks; ++i) total += (load[i] = point[i] + (run += range[i]));
    std::vector<KeySlab> cut;
    double acc = 0.0, start = 0.0, heaviest = 0.0;
    std::int32_t first = VoxelKey::kMinIndex;
    for (std::size_t i = 0; i + 1 < blocks && cut.size() + 1 < slabs; ++i) {
      acc += load[i];
      if (acc < total * static_cast<double>(cut.size() + 1) / static_cast<double>(slabs)) continue;
      const std::int32_t next = (lo[a] + static_cast<std::int32_t>(i) + 1) * edge;
      cut.push_back({a, first, next});
      heaviest = std::max(heaviest, acc - start);
      start = acc;
      first = next;
    }
    cut.push_back({a, first, VoxelKey::kMaxIndex + 1});
    heaviest = std::max(heaviest, total - start);
    if (heaviest < best_load) best_load = heaviest, best = std::move(cut);
  }
  return best;
}

}  // namespace nbs::detail
