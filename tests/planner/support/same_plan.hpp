// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Two closed-loop results describe the same plan (the oracle of the determinism and backend-equivalence tests): at
// every scan the same path (start pose, end position), the same number of measured points, the same ĉ_m, best
// utility and number of evaluated candidates.
#include "nbs_catch.hpp"

#include <cstddef>

namespace nbs::test {

template <class Result>
void check_same_plan(const Result& a, const Result& b) {
  REQUIRE(a.records.size() == b.records.size());
  for (std::size_t i = 0; i < a.records.size(); ++i) {
    INFO("scan " << i + 1);
    CHECK(a.records[i].path.start().pose().matrix() == b.records[i].path.start().pose().matrix());
    CHECK(a.records[i].path.end_position() == b.records[i].path.end_position());
    CHECK(a.records[i].points == b.records[i].points);
    CHECK(a.records[i].integration.estimated_coverage == b.records[i].integration.estimated_coverage);
    CHECK(a.records[i].planning.best_utility == b.records[i].planning.best_utility);
    CHECK(a.records[i].planning.evaluated == b.records[i].planning.evaluated);
  }
}

}  // namespace nbs::test
