// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include "nbs/termination/criteria.hpp"
#include "nbs/termination/process_control.hpp"

TEST_CASE("thesis termination: quality reached or n_abort (Sec. 4.6, Tab. 4.3)", "[termination]") {
  const auto t = nbs::thesis_termination(nbs::Parameters{});
  CHECK_FALSE(t.done({3, 0.79, 0.5}));
  CHECK_FALSE(t.done({3, 0.85, 0.19}));
  CHECK(t.done({3, 0.80, 0.20}));
  CHECK(t.done({30, 0.1, 0.0}));
  CHECK_FALSE(t.done({29, 0.1, 0.0}));

  const nbs::AllOf<nbs::CoverageAndDensityReached, nbs::MaxScansReached> both{{{0.5, 0.1}, nbs::MaxScansReached(4)}};
  CHECK_FALSE(both.done({3, 0.9, 0.9}));
  CHECK(both.done({4, 0.9, 0.9}));
  CHECK_THROWS_AS(nbs::CoverageAndDensityReached(1.2, 0.1), nbs::InvalidArgument);
  CHECK_THROWS_AS(nbs::MaxScansReached(0), nbs::InvalidArgument);
}

TEST_CASE("stop rule names: parse is format's inverse, an unknown name is refused naming it", "[termination]") {
  for (const nbs::StopRule r : {nbs::StopRule::settled, nbs::StopRule::thesis, nbs::StopRule::max_scans})
    CHECK(nbs::parse_stop_rule(nbs::format_stop_rule(r)) == r);
  CHECK_THROWS_WITH(nbs::parse_stop_rule("never"), nbs_test::Contains("'never'"));
  CHECK_THROWS_AS(nbs::parse_stop_rule("Thesis"), nbs::InvalidArgument);
}

TEST_CASE("process control switches to Hole Rescan once when coverage gain < 1 % (Eq. 4.38)", "[termination]") {
  nbs::ProcessControl pc;
  CHECK(pc.update(0.30) == nbs::SearchMode::BoundarySearch);  // first scan: no previous value
  CHECK(pc.update(0.50) == nbs::SearchMode::BoundarySearch);
  CHECK(pc.update(0.515) == nbs::SearchMode::BoundarySearch);  // +1.5 %
  CHECK_FALSE(pc.holes_pending());
  CHECK(pc.update(0.52) == nbs::SearchMode::HoleRescan);  // +0.5 % < 1 %
  CHECK(pc.holes_pending());
  pc.mark_holes_detected();
  CHECK_FALSE(pc.holes_pending());
  CHECK(pc.update(0.70) == nbs::SearchMode::HoleRescan);  // one-way switch
  CHECK_FALSE(pc.holes_pending());                        // holes are detected once
  CHECK_THROWS_AS(pc.update(1.5), nbs::InvalidArgument);
}
