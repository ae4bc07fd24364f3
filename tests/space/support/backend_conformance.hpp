// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// One conformance suite for every VoxelBackend: run by tests/space (native) and tests/octomap (OcTree).
#include "nbs_catch.hpp"

#include <map>
#include <mutex>
#include <thread>
#include <tuple>
#include <vector>

#include "nbs/space/backend.hpp"
#include "nbs/space/concepts.hpp"

namespace nbs::test {

// make_state(i) must return pairwise distinct, non-default states for i = 1, 2, ...
template <class B, class MakeState>
void check_backend_conformance(double resolution_m, MakeState make_state) {
  using State = backend_state_t<B>;
  static_assert(VoxelBackend<B>);
  B b = backend_traits<B>::make(resolution_m);
  const KeyBox range = key_range(b);

  // A fresh backend is empty and everything reads as unknown.
  REQUIRE(nbs::resolution_m(b) == resolution_m);
  REQUIRE(observed_count(b) == 0);
  REQUIRE(observed_key_bounds(b).empty());
  REQUIRE(voxel_state(b, VoxelKey{3, -4, 5}) == State{});
  REQUIRE_FALSE(is_observed(b, VoxelKey{3, -4, 5}));
  REQUIRE(range.contains(VoxelKey{-1000, 1000, 0}));
  const std::size_t empty_bytes = memory_bytes(b);

  // Keys on both sides of block and sign boundaries, far apart: the space grows in every direction.
  const std::vector<VoxelKey> keys = {{0, 0, 0},      {-1, 0, 0},      {7, 7, 7},         {8, 7, 7},
                                      {-8, -9, -1},   {100, -200, 30}, {-3000, 2500, -77}, {5, 5, 6},
                                      range.min,      range.max,       {range.max.x, range.min.y, 0}};
  std::map<std::tuple<int, int, int>, State> expected;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    set_voxel_state(b, keys[i], make_state(static_cast<int>(i + 1)));
    expected[{keys[i].x, keys[i].y, keys[i].z}] = make_state(static_cast<int>(i + 1));
  }
  for (std::size_t i = 0; i < keys.size(); ++i) {
    INFO("key " << i << ": " << keys[i].x << " " << keys[i].y << " " << keys[i].z);
    REQUIRE(voxel_state(b, keys[i]) == make_state(static_cast<int>(i + 1)));
    REQUIRE(is_observed(b, keys[i]));
  }
  REQUIRE_FALSE(is_observed(b, VoxelKey{1, 0, 0}));
  REQUIRE(voxel_state(b, VoxelKey{6, 7, 7}) == State{});
  REQUIRE(observed_count(b) == keys.size());
  REQUIRE(memory_bytes(b) > empty_bytes);

  // Iteration visits exactly the written voxels with their states.
  std::map<std::tuple<int, int, int>, State> seen;
  for_each_voxel(b, [&](const VoxelKey& k, const State& s) {
    REQUIRE(seen.count({k.x, k.y, k.z}) == 0);
    seen[{k.x, k.y, k.z}] = s;
  });
  REQUIRE(seen == expected);

  KeyBox box;
  for (const auto& k : keys) box.extend(k);
  const KeyBox got = observed_key_bounds(b);
  REQUIRE(got.min == box.min);
  REQUIRE(got.max == box.max);

  // Overwriting keeps the count.
  set_voxel_state(b, keys[0], make_state(1000));
  REQUIRE(voxel_state(b, keys[0]) == make_state(1000));
  REQUIRE(observed_count(b) == keys.size());

  // Writes outside the key range are refused and change nothing.
  const VoxelKey outside{range.max.x + 1, 0, 0};
  REQUIRE_THROWS_AS(set_voxel_state(b, outside, make_state(1)), InvalidArgument);
  REQUIRE(observed_count(b) == keys.size());

  // Capability: threads writing disjoint blocks at once, one ConcurrentWriter each (thread t: the blocks with block
  // x key (100 >> kEdgeBits) + t, new blocks and the block of the key {100, −200, 30} written above among them).
  if constexpr (ConcurrentBlockBackend<B>) {
    constexpr int kThreads = 3, kEdge = B::kEdge;
    const auto key_of = [&](int t, int i) {
      return VoxelKey{((100 >> B::kEdgeBits) + t) * kEdge + i % kEdge, -200 + (i / kEdge) % 24, 30 + i / (kEdge * 24)};
    };
    constexpr int kPerThread = kEdge * 24 * 3;
    std::mutex m;
    std::vector<std::thread> pool;
    for (int t = 0; t < kThreads; ++t)
      pool.emplace_back([&, t] {
        typename B::ConcurrentWriter w(b, m);
        for (int i = 0; i < kPerThread; ++i) {
          const VoxelKey k = key_of(t, i);
          auto& blk = w.block(B::block_id(k));
          blk.put(B::local_index(k), make_state(2000 + t * kPerThread + i));
          w.note_observed(blk, B::local_index(k));
        }
        w.commit();
      });
    for (auto& th : pool) th.join();
    std::size_t fresh = 0;
    for (int t = 0; t < kThreads; ++t)
      for (int i = 0; i < kPerThread; ++i) {
        const VoxelKey k = key_of(t, i);
        REQUIRE(voxel_state(b, k) == make_state(2000 + t * kPerThread + i));
        fresh += expected.count({k.x, k.y, k.z}) == 0 ? 1 : 0;
      }
    REQUIRE(fresh == kThreads * kPerThread - 1);  // {100, −200, 30} was written before
    REQUIRE(observed_count(b) == keys.size() + fresh);
  }
}

}  // namespace nbs::test
