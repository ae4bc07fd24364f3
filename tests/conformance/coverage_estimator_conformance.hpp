// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Conformance suite of the CoverageEstimator concept (nbs/coverage/coverage_estimator.hpp):
// check_coverage_estimator_conformance(estimator, empty_mesh, closed_mesh, open_mesh, space, params, box) checks the
// contract every ĉ_m model keeps — a mesh without triangles gives 0; ĉ_m ∈ [0, 1]; deterministic, a copy gives the
// same; a closed mesh (no border loop) gives 1 and no unseen samples; unseen samples (CoverageResult::unseen, may be
// empty) are finite with area and edge distance ≥ 0 and the same on every call — for any model; the forms' values on an open box are checked by
// test_coverage_estimator_conformance.cpp against the analytic areas.
#include "nbs_catch.hpp"

#include "nbs/coverage/coverage_estimator.hpp"

namespace nbs::conformance {

template <class C, class Mesh, class Space>
void check_coverage_estimator_conformance(const C& estimator, const Mesh& empty_mesh, const Mesh& closed_mesh,
                                          const Mesh& open_mesh, const Space& space, const Parameters& params,
                                          const Aabb& box) {
  static_assert(CoverageEstimator<C, Mesh, Space>);
  const CoverageResult none = estimator.estimate(CoverageInput<Mesh, Space>{empty_mesh, space, params, box});
  CHECK(none.coverage == 0.0);
  CHECK(none.holes == 0);
  const CoverageResult closed = estimator.estimate(CoverageInput<Mesh, Space>{closed_mesh, space, params, box});
  CHECK(closed.coverage == Approx(1.0).margin(1e-12));
  CHECK(none.unseen.empty());
  CHECK(closed.unseen.empty());
  const CoverageInput<Mesh, Space> in{open_mesh, space, params, box};
  const CoverageResult a = estimator.estimate(in);
  CHECK(a.coverage >= 0.0);
  CHECK(a.coverage <= 1.0);
  const C copy = estimator;
  const CoverageResult b = copy.estimate(in);
  CHECK(a.coverage == b.coverage);
  CHECK(a.holes == b.holes);
  CHECK(estimator.estimate(in).coverage == a.coverage);
  REQUIRE(a.unseen.size() == b.unseen.size());
  for (std::size_t i = 0; i < a.unseen.size(); ++i) {
    const UnseenSample& u = a.unseen[i];
    CHECK(u.position.allFinite());
    CHECK(u.area_m2 >= 0.0);
    CHECK(u.edge_distance_m >= 0.0);
    CHECK(u.position == b.unseen[i].position);
    CHECK(u.area_m2 == b.unseen[i].area_m2);
  }
}

}  // namespace nbs::conformance
