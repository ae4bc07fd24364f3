#include <catch2/catch.hpp>

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
