// SPDX-License-Identifier: BSD-3-Clause
// TerminationCriterion conformance: the thesis criteria (Sec. 4.6), AllOf / AnyOf, default_termination and a
// minimal user-written criterion, each against its documented rule.
#include "termination_conformance.hpp"

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

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
  check_termination_conformance(nbs::thesis_termination(params), [](const ModelProgress& p) {
    return p.scans >= 12 || (p.estimated_coverage >= 0.95 && p.mean_density >= 0.2);
  });
  check_termination_conformance(nbs::SelectableTermination(params, nbs::StopRule::thesis), [](const ModelProgress& p) {
    return p.scans >= 12 || (p.estimated_coverage >= 0.95 && p.mean_density >= 0.2);
  });
  check_termination_conformance(nbs::SelectableTermination(params, nbs::StopRule::max_scans),
                                [](const ModelProgress& p) { return p.scans >= 12; });
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

TEST_CASE("CoverageSettled: held on consecutive scans, settled or stalled within a width, against a brute-force "
          "replay",
          "[conformance][termination]") {
  using nbs::ModelProgress;
  // On the grid there is no history: never done (and the criterion is not monotone, it reads the history).
  nbs::conformance::check_termination_conformance(nbs::CoverageSettled{}, [](const ModelProgress&) { return false; },
                                                  false);
  // The oracle: the rule of benchmarks/stop_rule_table.py's settled_rule, per prefix of a ĉ_m sequence — held
  // (≥ 0.9 on the last 2 scans), settled (last ≥ 0.75, the last 3 within 0.03) or stalled (last ≥ 0.5, the last 5
  // within 0.03), density ≥ 0.2.
  const auto still = [](const std::vector<double>& h, double level, std::size_t w) {
    const std::size_t n = h.size();
    if (n < w || h[n - 1] < level) return false;
    double lo = 1.0, hi = 0.0;
    for (std::size_t i = n - w; i < n; ++i) lo = std::min(lo, h[i]), hi = std::max(hi, h[i]);
    return hi - lo < 0.03;
  };
  const auto oracle = [&](const std::vector<double>& h, double density) {
    const std::size_t n = h.size();
    if (density < 0.2 || n == 0) return false;
    if (n >= 2 && h[n - 1] >= 0.9 && h[n - 2] >= 0.9) return true;
    return still(h, 0.75, 3) || still(h, 0.5, 5);
  };
  const nbs::CoverageSettled rule;
  // Hand cases: one high value does not stop; two do; a plateau above the floor does; one below it does not unless
  // it lasts 5 scans above the stall floor.
  const std::vector<std::pair<std::vector<double>, bool>> cases{
      {{0.95}, false},
      {{0.5, 0.95}, false},
      {{0.91, 0.95}, true},
      {{0.78, 0.79, 0.80}, true},
      {{0.70, 0.72, 0.71}, false},
      {{0.76, 0.80, 0.78}, false},
      {{0.2, 0.8, 0.81, 0.79}, true},
      {{0.70, 0.71, 0.70, 0.72, 0.71}, true},
      {{0.62, 0.70, 0.71, 0.70, 0.72, 0.71}, true},
      {{0.66, 0.71, 0.70, 0.72, 0.71}, false},
      {{0.46, 0.47, 0.46, 0.47, 0.46}, false}};
  for (const auto& [h, expected] : cases) {
    INFO("history of " << h.size() << ", last " << h.back());
    CHECK(rule.done(ModelProgress{static_cast<int>(h.size()), h.back(), 0.5, h}) == expected);
    CHECK(rule.done(ModelProgress{static_cast<int>(h.size()), h.back(), 0.1, h}) == false);  // density not reached
  }
  // Random ĉ_m walks, rising (step 0.08) and creeping (step 0.02): every prefix against the oracle.
  std::uint64_t state = 7;
  const auto uniform = [&] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) * 0x1.0p-53;
  };
  std::size_t stops = 0, stalls = 0;
  for (int walk = 0; walk < 1000; ++walk) {
    std::vector<double> h;
    double c = uniform();
    const double step = walk % 2 == 0 ? 0.08 : 0.02;
    for (int k = 0; k < 12; ++k) {
      c = std::clamp(c + step * (uniform() - 0.4), 0.0, 1.0);
      h.push_back(c);
      const double d = uniform() < 0.1 ? 0.1 : 0.5;
      const bool got = rule.done(ModelProgress{static_cast<int>(h.size()), c, d, h});
      REQUIRE(got == oracle(h, d));
      stops += got ? 1 : 0;
      stalls += got && c < 0.75 ? 1 : 0;
    }
  }
  CHECK(stops > 100);  // the walks exercise every arm
  CHECK(stalls > 20);
  // The default termination and the run-time choice of it: the same rule, or n_abort; density from Parameters.
  nbs::Parameters params;
  params.max_scans = 9;
  params.target_density = 0.3;
  const auto def = nbs::default_termination(params);
  const nbs::SelectableTermination chosen(params);
  CHECK(chosen.rule == nbs::StopRule::settled);
  const std::vector<double> flat{0.80, 0.81, 0.80};
  for (const double d : {0.25, 0.35})
    for (int n : {3, 9}) {
      const ModelProgress p{n, flat.back(), d, flat};
      const bool want = n >= 9 || (d >= 0.3 && oracle(flat, d));
      CHECK(def.done(p) == want);
      CHECK(chosen.done(p) == want);
    }
  // Bad settings are refused.
  CHECK_THROWS_AS(nbs::CoverageSettled(1.5, 2, 0.75, 3, 0.03, 0.2), nbs::InvalidArgument);
  CHECK_THROWS_AS(nbs::CoverageSettled(0.9, 0, 0.75, 3, 0.03, 0.2), nbs::InvalidArgument);
  CHECK_THROWS_AS(nbs::CoverageSettled(0.9, 2, 0.75, 1, 0.03, 0.2), nbs::InvalidArgument);
  CHECK_THROWS_AS(nbs::CoverageSettled(0.9, 2, 0.75, 3, -0.1, 0.2), nbs::InvalidArgument);
  CHECK_THROWS_AS(nbs::CoverageSettled(0.9, 2, 0.75, 3, 0.03, 0.2, 1.5, 5), nbs::InvalidArgument);
  CHECK_THROWS_AS(nbs::CoverageSettled(0.9, 2, 0.75, 3, 0.03, 0.2, 0.5, 1), nbs::InvalidArgument);
  CHECK_NOTHROW(nbs::CoverageSettled(0.9, 2, 0.75, 3, 0.03, 0.2, 0.5, 2));
}
