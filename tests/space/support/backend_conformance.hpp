// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// One conformance suite for every VoxelBackend: run by tests/space (native) and tests/octomap (OcTree).
#include "nbs_catch.hpp"

#include <map>
#include <tuple>
#include <vector>

#include "nbs/space/backend.hpp"

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
}

}  // namespace nbs::test
