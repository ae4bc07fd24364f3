// SPDX-License-Identifier: BSD-3-Clause
// TerminationCriterion conformance: the thesis criteria (Sec. 4.6), AllOf / AnyOf, default_termination and a
// minimal user-written criterion, each against its documented rule.
#include "termination_conformance.hpp"

namespace {

/// The user-written criterion: stop once ĉ_m reaches 90 % (density ignored).
struct CoverageOnly {
  [[nodiscard]] bool done(const nbs::ModelProgress& p) const { return p.estimated_coverage >= 0.9; }
};

}  // namespace

TEST_CASE("TerminationCriterion conformance: every model and a user-written one", "[conformance][termination]") {
  using nbs::ModelProgress;
  using nbs::conformance::check_termination_conformance;
  const auto quality = [](const ModelProgress& p) { return p.estimated_coverage >= 0.8 && p.mean_density >= 0.2; };
  const auto n_abort = [](const ModelProgress& p) { return p.scans >= 30; };
  check_termination_conformance(nbs::CoverageAndDensityReached{}, quality);
  check_termination_conformance(nbs::CoverageAndDensityReached(0.5, 0.0),
                                [](const ModelProgress& p) { return p.estimated_coverage >= 0.5; });
  check_termination_conformance(nbs::MaxScansReached{}, n_abort);
  check_termination_conformance(nbs::MaxScansReached(1), [](const ModelProgress& p) { return p.scans >= 1; });
  check_termination_conformance(CoverageOnly{}, [](const ModelProgress& p) { return p.estimated_coverage >= 0.9; });

  using Any = nbs::AnyOf<nbs::CoverageAndDensityReached, nbs::MaxScansReached, CoverageOnly>;
  check_termination_conformance(Any{{nbs::CoverageAndDensityReached{}, nbs::MaxScansReached(10), CoverageOnly{}}},
                                [&](const ModelProgress& p) {
                                  return quality(p) || p.scans >= 10 || p.estimated_coverage >= 0.9;
                                });
  using All = nbs::AllOf<nbs::MaxScansReached, CoverageOnly>;
  check_termination_conformance(All{{nbs::MaxScansReached(5), CoverageOnly{}}}, [](const ModelProgress& p) {
    return p.scans >= 5 && p.estimated_coverage >= 0.9;
  });
  // Empty compositions: AllOf<> is always done, AnyOf<> never (fold identities).
  check_termination_conformance(nbs::AllOf<>{}, [](const ModelProgress&) { return true; });
  check_termination_conformance(nbs::AnyOf<>{}, [](const ModelProgress&) { return false; });

  nbs::Parameters params;
  params.max_scans = 12;
  params.target_coverage = 0.95;
  check_termination_conformance(nbs::default_termination(params), [](const ModelProgress& p) {
    return p.scans >= 12 || (p.estimated_coverage >= 0.95 && p.mean_density >= 0.2);
  });
}

TEST_CASE("termination conformance can fail: a non-monotone criterion is caught", "[conformance][termination]") {
  // Done only at exactly 10 scans: the oracle agrees, monotonicity does not. Checked by hand, not by REQUIRE.
  struct OnlyAtTen {
    [[nodiscard]] bool done(const nbs::ModelProgress& p) const { return p.scans == 10; }
  };
  const OnlyAtTen c;
  bool violated = false;
  for (const auto& p : nbs::conformance::progress_grid())
    for (const auto& q : nbs::conformance::progress_grid())
      violated = violated || (c.done(p) && q.scans >= p.scans && q.estimated_coverage >= p.estimated_coverage &&
                              q.mean_density >= p.mean_density && !c.done(q));
  CHECK(violated);
}
