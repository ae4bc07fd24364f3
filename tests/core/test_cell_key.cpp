// SPDX-License-Identifier: BSD-3-Clause
// detail::pack_cell_key (21 bits per axis, shared by the spatial hash, the scan normals and the viewer's decimation):
// round trip and lexicographic order at the ends of the range, the range check of the checked form (out of range,
// NaN, infinity throw naming the caller), and CellKeyMap against std::map.
#include "nbs_catch.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <random>
#include <vector>

#include "nbs/core/detail/cell_key.hpp"

using nbs::Vec3;
using nbs::detail::kMaxCellIndex;
using nbs::detail::kMinCellIndex;

TEST_CASE("cell key: round trip and (x, y, z) order over the whole range", "[core][cell_key]") {
  const std::vector<int> values{kMinCellIndex, kMinCellIndex + 1, -2, -1, 0, 1, 2, kMaxCellIndex - 1, kMaxCellIndex};
  std::vector<Eigen::Vector3i> cells;
  for (int x : values)
    for (int y : values)
      for (int z : values) cells.emplace_back(x, y, z);  // lexicographic order
  std::uint64_t previous = 0;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    REQUIRE(nbs::detail::cell_in_key_range(cells[i]));
    const std::uint64_t key = nbs::detail::pack_cell_key(cells[i]);
    CHECK(nbs::detail::unpack_cell_key(key) == cells[i]);
    if (i > 0) CHECK(key > previous);
    previous = key;
  }
  CHECK_FALSE(nbs::detail::cell_in_key_range(Eigen::Vector3i(kMaxCellIndex + 1, 0, 0)));
  CHECK_FALSE(nbs::detail::cell_in_key_range(Eigen::Vector3i(0, kMinCellIndex - 1, 0)));
}

TEST_CASE("cell key: the checked form floors, and throws for cells out of range", "[core][cell_key]") {
  using nbs::detail::pack_cell_key_checked;
  CHECK(pack_cell_key_checked(Vec3(0.5, -0.5, 2.9), "t") == nbs::detail::pack_cell_key({0, -1, 2}));
  CHECK(pack_cell_key_checked(Vec3(kMaxCellIndex + 0.9, kMinCellIndex, 0.0), "t") ==
        nbs::detail::pack_cell_key({kMaxCellIndex, kMinCellIndex, 0}));
  CHECK_THROWS_WITH(pack_cell_key_checked(Vec3(kMaxCellIndex + 1.0, 0.0, 0.0), "viewer decimation"),
                    nbs_test::Contains("viewer decimation: cell coordinates"));
  CHECK_THROWS_AS(pack_cell_key_checked(Vec3(0.0, kMinCellIndex - 0.5, 0.0), "t"), nbs::InvalidArgument);
  CHECK_THROWS_AS(pack_cell_key_checked(Vec3(0.0, 0.0, std::numeric_limits<double>::quiet_NaN()), "t"),
                  nbs::InvalidArgument);
  CHECK_THROWS_AS(pack_cell_key_checked(Vec3(std::numeric_limits<double>::infinity(), 0.0, 0.0), "t"),
                  nbs::InvalidArgument);
  CHECK_FALSE(nbs::detail::cell_index(Vec3(1e300, 0.0, 0.0)).has_value());
}

TEST_CASE("cell key map: inserts and finds like std::map (growing from a small table)", "[core][cell_key]") {
  std::mt19937_64 rng(3);
  std::uniform_int_distribution<int> u(-40, 40);
  nbs::detail::CellKeyMap map(1);
  std::map<std::uint64_t, std::uint32_t> oracle;
  for (std::uint32_t i = 0; i < 5000; ++i) {
    const std::uint64_t key = nbs::detail::pack_cell_key({u(rng), u(rng), u(rng)});
    const auto [value, fresh] = map.try_emplace(key, i);
    const auto [it, oracle_fresh] = oracle.try_emplace(key, i);
    CHECK(fresh == oracle_fresh);
    CHECK(value == it->second);
  }
  CHECK(map.size() == oracle.size());
  for (const auto& [key, value] : oracle) CHECK(map.find(key) == value);
  CHECK(map.find(nbs::detail::pack_cell_key({41, 0, 0})) == nbs::detail::CellKeyMap::kNone);
}
