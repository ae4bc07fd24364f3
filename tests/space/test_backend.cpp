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
  nbs::HashedBlockBackend<nbs::ThesisState> b(0.01);
  b.set({0, 0, 0}, nbs::ThesisState{1, 2, 0, 0, 0});
  b.set({7, 7, 7}, nbs::ThesisState{1, 2, 0, 0, 0});
  REQUIRE(b.block_count() == 1);
  const std::size_t one = b.memory_bytes();
  b.set({8, 7, 7}, nbs::ThesisState{1, 2, 0, 0, 0});
  REQUIRE(b.block_count() == 2);
  // One more block costs its 512 states (8 B) + stamps (1 B) + observed mask (64 B) + a hash-map node.
  REQUIRE(b.memory_bytes() - one >= 512 * 9 + 64);
  REQUIRE(b.memory_bytes() - one <= 512 * 9 + 64 + 64);
}
