// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include <algorithm>
#include <random>
#include <set>
#include <tuple>

#include "nbs/space/hashed_block_backend.hpp"
#include "nbs/space/log_odds_model.hpp"
#include "nbs/space/thesis_model.hpp"
#include "support/backend_conformance.hpp"

TEST_CASE("HashedBlockBackend<LogOddsState> passes the backend conformance suite", "[space][backend]") {
  nbs::test::check_backend_conformance<nbs::HashedBlockBackend<nbs::LogOddsState>>(
      0.005, [](int i) { return nbs::LogOddsState{0.25f * static_cast<float>(i)}; });
}

TEST_CASE("HashedBlockBackend<ThesisState> passes the backend conformance suite", "[space][backend]") {
  nbs::test::check_backend_conformance<nbs::HashedBlockBackend<nbs::ThesisState>>(0.002, [](int i) {
    nbs::ThesisState s;
    s.surf = static_cast<std::int16_t>(i);
    s.free = static_cast<std::int16_t>(-i);
    return s;
  });
}

TEST_CASE("HashedBlockBackend keeps voxel states compact", "[space][backend]") {
  STATIC_REQUIRE(sizeof(nbs::ThesisState) == 8);
  STATIC_REQUIRE(sizeof(nbs::LogOddsState) == 4);
  using Backend = nbs::HashedBlockBackend<nbs::ThesisState>;
  Backend b(0.01);
  nbs::ThesisState free_only;
  free_only.free = -415;
  free_only.direction = 0x1234;
  b.set({0, 0, 0}, free_only);
  b.set({7, 7, 7}, free_only);
  REQUIRE(b.block_count() == 1);
  const std::size_t one = b.memory_bytes();
  b.set({8, 7, 7}, free_only);
  REQUIRE(b.block_count() == 2);
  // A free-space block: free + direction (4 B per voxel), observed and touched masks (2 × 64 B), two epochs,
  // the side-car pointer and a hash-map node.
  const std::size_t free_block = b.memory_bytes() - one;
  REQUIRE(free_block >= 512 * 4 + 128);
  REQUIRE(free_block <= 512 * 4 + 128 + 80);
  // Surface evidence in a block allocates its side-car of surf + spec (3 B per voxel), once.
  nbs::ThesisState surface = free_only;
  surface.surf = 868;
  surface.spec = 17;
  const std::size_t before = b.memory_bytes();
  b.set({9, 7, 7}, surface);
  REQUIRE(b.memory_bytes() - before == 512 * 3);
  b.set({10, 7, 7}, surface);
  REQUIRE(b.memory_bytes() - before == 512 * 3);
  REQUIRE(b.get({9, 7, 7}) == surface);
  REQUIRE(b.get({8, 7, 7}) == free_only);
  REQUIRE(b.get({11, 7, 7}) == nbs::ThesisState{});
}

TEST_CASE("HashedBlockBackend::all_touched matches a voxel-by-voxel check", "[space][backend]") {
  using BE = nbs::HashedBlockBackend<nbs::ThesisState>;
  BE be(0.01);
  (void)be.next_epoch();
  std::mt19937_64 rng(5);
  std::uniform_int_distribution<int> c(-10, 9), d(0, 3), coin(0, 5);
  std::set<std::tuple<int, int, int>> touched;
  for (int x = -10; x < 10; ++x)  // touch 5 in 6 voxels of a 20³ region spanning several blocks
    for (int y = -10; y < 10; ++y)
      for (int z = -10; z < 10; ++z)
        if (coin(rng) != 0) {
          const nbs::VoxelKey k{x, y, z};
          (void)be.block(BE::block_id(k)).touch(BE::local_index(k));
          touched.insert({x, y, z});
        }
  int full = 0;
  for (int i = 0; i < 20000; ++i) {
    const nbs::VoxelKey a{c(rng), c(rng), c(rng)};
    const nbs::VoxelKey b{a.x + d(rng) - 1, a.y + d(rng) - 1, a.z + d(rng) - 1};
    bool all = true;
    for (int x = std::min(a.x, b.x); x <= std::max(a.x, b.x); ++x)
      for (int y = std::min(a.y, b.y); y <= std::max(a.y, b.y); ++y)
        for (int z = std::min(a.z, b.z); z <= std::max(a.z, b.z); ++z) all = all && touched.count({x, y, z}) == 1;
    REQUIRE(be.all_touched(a, b) == all);
    full += all ? 1 : 0;
  }
  REQUIRE(full > 1000);
  (void)be.next_epoch();  // a new scan: nothing is touched
  REQUIRE_FALSE(be.all_touched(nbs::VoxelKey{0, 0, 0}, nbs::VoxelKey{0, 0, 0}));
}
