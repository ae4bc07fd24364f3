// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Conformance harness for nbs::TerminationCriterion (include/nbs/termination/criteria.hpp) over a grid of
// ModelProgress values (n_s 0..40, ĉ_m and d̄_m in [0, 1] including the thresholds of Tab. 4.3). Checked contract:
//  - done(p) is side-effect free: asking twice, or asking a copy, gives the same answer;
//  - it equals the oracle (the documented rule) everywhere on the grid;
//  - with `monotone`, more progress never undoes "done": done(p) implies done(p') for p' ≥ p in n_s, ĉ_m and d̄_m
//    (true of every criterion in the repo; the loop relies on it only through n_abort).
#include "nbs_catch.hpp"

#include <functional>
#include <vector>

#include "nbs/termination/criteria.hpp"

namespace nbs::conformance {

/// The progress grid: scans × coverage × density.
inline std::vector<ModelProgress> progress_grid() {
  const std::vector<int> scans = {0, 1, 2, 5, 9, 10, 11, 29, 30, 31, 40};
  const std::vector<double> fractions = {0.0, 0.1, 0.199, 0.2, 0.201, 0.5, 0.799, 0.8, 0.801, 0.95, 1.0};
  std::vector<ModelProgress> out;
  for (int n : scans)
    for (double c : fractions)
      for (double d : fractions) out.push_back({n, c, d});
  return out;
}

template <class T>
void check_termination_conformance(const T& criterion, const std::function<bool(const ModelProgress&)>& oracle,
                                   bool monotone = true) {
  static_assert(TerminationCriterion<T>);
  const std::vector<ModelProgress> grid = progress_grid();
  const T copy = criterion;
  for (const ModelProgress& p : grid) {
    INFO("n_s " << p.scans << ", c_m " << p.estimated_coverage << ", d_m " << p.mean_density);
    const bool d = static_cast<bool>(criterion.done(p));
    REQUIRE(static_cast<bool>(criterion.done(p)) == d);
    REQUIRE(static_cast<bool>(copy.done(p)) == d);
    REQUIRE(d == oracle(p));
  }
  if (monotone) {
    for (const ModelProgress& p : grid) {
      if (!criterion.done(p)) continue;
      for (const ModelProgress& q : grid) {
        if (q.scans < p.scans || q.estimated_coverage < p.estimated_coverage || q.mean_density < p.mean_density)
          continue;
        if (!criterion.done(q))
          FAIL("done at (" << p.scans << ", " << p.estimated_coverage << ", " << p.mean_density
                           << ") but not at (" << q.scans << ", " << q.estimated_coverage << ", " << q.mean_density
                           << ")");
      }
    }
  }
}

}  // namespace nbs::conformance
