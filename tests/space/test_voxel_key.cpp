// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include <cmath>
#include <limits>
#include <map>
#include <tuple>
#include <random>

#include "nbs/space/key_slots.hpp"
#include "nbs/space/voxel_key.hpp"
#include "nbs_random.hpp"

using nbs::VoxelKey;

TEST_CASE("VoxelKey packs 21 bits per axis losslessly", "[space][key]") {
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<std::int32_t> d(VoxelKey::kMinIndex, VoxelKey::kMaxIndex);
  for (int i = 0; i < 10000; ++i) {
    const VoxelKey k{d(rng), d(rng), d(rng)};
    REQUIRE(VoxelKey::unpack(k.pack()) == k);
  }
  const VoxelKey lo{VoxelKey::kMinIndex, VoxelKey::kMinIndex, VoxelKey::kMinIndex};
  const VoxelKey hi{VoxelKey::kMaxIndex, VoxelKey::kMaxIndex, VoxelKey::kMaxIndex};
  REQUIRE(VoxelKey::unpack(lo.pack()) == lo);
  REQUIRE(VoxelKey::unpack(hi.pack()) == hi);
  REQUIRE(lo.pack() != hi.pack());
  REQUIRE_FALSE(VoxelKey{VoxelKey::kMaxIndex + 1, 0, 0}.valid());
}

TEST_CASE("VoxelGrid maps coordinates with floor(x / l_v)", "[space][key]") {
  const nbs::VoxelGrid g(0.005);
  REQUIRE(*g.key_of(nbs::Vec3(0.0, 0.0049, -0.0001)) == VoxelKey{0, 0, -1});
  REQUIRE(*g.key_of(nbs::Vec3(0.0051, -0.0051, 0.0151)) == VoxelKey{1, -2, 3});
  REQUIRE((g.center(VoxelKey{1, -2, 3}) - nbs::Vec3(0.0075, -0.0075, 0.0175)).norm() < 1e-15);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  REQUIRE_FALSE(g.key_of(nbs::Vec3(nan, 0, 0)).has_value());
  REQUIRE_FALSE(g.key_of(nbs::Vec3(0, std::numeric_limits<double>::infinity(), 0)).has_value());
  REQUIRE_FALSE(g.key_of(nbs::Vec3(0, 0, 1e5)).has_value());  // beyond 2^20 · 5 mm
  REQUIRE(g.key_of(nbs::Vec3(0, 0, 5000.0)).has_value());
  REQUIRE_THROWS_AS(nbs::VoxelGrid(0.0), nbs::InvalidArgument);
  REQUIRE_THROWS_AS(nbs::VoxelGrid(-1.0), nbs::InvalidArgument);
  REQUIRE_THROWS_AS(nbs::VoxelGrid(nan), nbs::InvalidArgument);
}

TEST_CASE("VoxelGrid::in_voxel(p, k) is key_of(p) == k", "[space][key]") {
  const nbs::VoxelGrid g(0.003);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  std::uniform_int_distribution<int> q(-40, 40), dk(-1, 1);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int i = 0; i < 20000; ++i) {
    // random points, and points exactly on voxel faces (multiples of l_v) where floor decides
    const nbs::Vec3 p = i % 2 == 0 ? nbs_test::random_vec3(u, rng) : nbs_test::random_vec3(q, rng) * 0.003;
    const VoxelKey k = *g.key_of(p);
    REQUIRE(g.in_voxel(p, k));
    const VoxelKey n{k.x + dk(rng), k.y + dk(rng), k.z + dk(rng)};
    REQUIRE(g.in_voxel(p, n) == (n == k));
  }
  REQUIRE_FALSE(g.in_voxel(nbs::Vec3(nan, 0, 0), VoxelKey{0, 0, 0}));
  REQUIRE_FALSE(g.in_voxel(nbs::Vec3(0, 0, 1e9), VoxelKey{0, 0, VoxelKey::kMaxIndex}));
}

TEST_CASE("KeySlots: dense and hashed modes agree with a std::map oracle; keys outside the box are ignored",
          "[space]") {
  const nbs::KeyBox box{{-3, 2, -5}, {4, 6, 1}};  // 8 x 5 x 7 = 280 voxels
  for (const std::size_t limit : {std::size_t{1000}, std::size_t{100}}) {
    nbs::KeySlots slots(box, limit);
    CHECK(slots.dense() == (limit == 1000));
    std::map<std::tuple<int, int, int>, std::int32_t> oracle;
    std::mt19937 rng(3);
    std::uniform_int_distribution<int> coord(-7, 8);
    for (std::int32_t i = 0; i < 400; ++i) {
      const nbs::VoxelKey k{coord(rng), coord(rng), coord(rng)};
      slots.assign(k, i);
      if (box.contains(k)) oracle[{k.x, k.y, k.z}] = i;
    }
    REQUIRE(!oracle.empty());
    for (int x = -8; x <= 9; ++x)
      for (int y = -8; y <= 9; ++y)
        for (int z = -8; z <= 9; ++z) {
          const auto it = oracle.find({x, y, z});
          CHECK(slots.find({x, y, z}) == (it == oracle.end() ? nbs::KeySlots::kNone : it->second));
        }
  }
  const nbs::KeySlots none(nbs::KeyBox{});
  CHECK(none.find({0, 0, 0}) == nbs::KeySlots::kNone);
}
