// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include <cmath>
#include <numbers>

#include "nbs/utility/utility_function.hpp"

TEST_CASE("omega schedule of Eq. 4.31", "[utility]") {
  CHECK(nbs::modeling_weight(0) == 0.0);
  CHECK(nbs::modeling_weight(5) == Approx(0.5));  // n_q = 5: equal weight after five scans
  CHECK(nbs::modeling_weight(15) == Approx(0.75));
  CHECK(nbs::modeling_weight(3, 1) == Approx(0.75));
  for (int n = 0; n < 30; ++n) CHECK(nbs::modeling_weight(n + 1) > nbs::modeling_weight(n));
  CHECK_THROWS_AS(nbs::modeling_weight(-1), nbs::InvalidArgument);
  CHECK_THROWS_AS(nbs::modeling_weight(1, 0), nbs::InvalidArgument);
}

TEST_CASE("voxel entropy (Eq. 4.32 summand) and quality (Eq. 4.33)", "[utility]") {
  CHECK(nbs::voxel_entropy(0.5) == Approx(1.0));
  CHECK(nbs::voxel_entropy(0.0) == 0.0);
  CHECK(nbs::voxel_entropy(1.0) == 0.0);
  CHECK(nbs::voxel_entropy(0.25) == Approx(-(0.25 * std::log2(0.25) + 0.75 * std::log2(0.75))));
  CHECK(nbs::voxel_entropy(0.1) == Approx(nbs::voxel_entropy(0.9)));
  CHECK_THROWS_AS(nbs::voxel_entropy(1.5), nbs::InvalidArgument);

  const double cut = 70.0 * std::numbers::pi / 180.0;
  CHECK(nbs::voxel_quality(0.4, 0.6, 0.7) == Approx(0.7 * 0.6 + 0.3 * 0.6));
  CHECK(nbs::voxel_quality(0.0, 1.0, 0.7) == 1.0);  // complete and dense: perfect quality
  CHECK(nbs::voxel_quality(1.0, 0.0, 0.7) == 0.0);  // all border edges, no density: none
  CHECK(nbs::voxel_rescan_value(0.4, 0.6, 0.1, 0.7, cut) == Approx(1.0 - (0.7 * 0.6 + 0.3 * 0.6)));
  CHECK(nbs::voxel_rescan_value(0.4, 0.6, cut, 0.7, cut) == 0.0);  // θ ≥ 70°: re-scan is worthless
  CHECK(nbs::weighted_utility(0.8, 0.3, 0.25) == Approx(0.75 * 0.8 + 0.25 * 0.3));
}
