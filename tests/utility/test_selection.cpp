// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include <set>
#include <string>
#include <vector>

#include "nbs/utility/selection.hpp"
#include "test_terms_fixtures.hpp"

using namespace nbs;


TEST_CASE("selection codes round-trip and bad codes name the valid ones", "[utility][selection]") {
  std::set<std::string> codes;
  for (Selection s : kAllSelections) {
    const std::string c(format_selection(s));
    codes.insert(c);
    CHECK(parse_selection(c) == s);
  }
  CHECK(codes.size() == kAllSelections.size());
  CHECK(parse_selection(" c ") == Selection::ig_quality);
  CHECK(parse_selection("rse") == Selection::rear_side_entropy);
  CHECK_THROWS_AS(parse_selection(""), InvalidArgument);
  CHECK_THROWS_AS(parse_selection("IGQ"), InvalidArgument);
  CHECK_THROWS_WITH(parse_selection("X"), nbs_test::Contains("'X'") && nbs_test::Contains("R, I, Q, C, OA"));
}

TEST_CASE("evaluate_selection runs every criterion, matching the terms", "[utility][selection]") {
  auto space = nbs_test::make_space();
  space.integrate(nbs_test::rows_scan({{5, 5}, {5, 6}, {4, 5}}, 7));
  LaserStripeProfiler lsp;
  lsp.points_per_profile = 7;
  lsp.fan_angle_rad = 0.3;
  lsp.range = {0.01, 0.3};
  lsp.profile_spacing_m = 0.01;
  std::vector<LinearScanPath> cands;
  for (const Vec3& p : {Vec3(0.2, 0.05, 0.05), Vec3(-0.1, 0.05, 0.055), Vec3(0.05, 0.05, 0.2)}) {
    const Viewpoint v = Viewpoint::look_at(p, Vec3(0.05, 0.05, 0.05), Vec3::UnitY());
    cands.emplace_back(v, p + 0.02 * v.y_axis());
  }
  const double n_v = non_free_voxel_count(space);
  SelectionSetting sel;
  sel.n_scans = 4;
  for (Selection s : kAllSelections) {
    sel.selection = s;
    const auto a = evaluate_selection(std::span<const LinearScanPath>(cands), lsp, space, sel, nbs_test::threads(1));
    const auto b = evaluate_selection(std::span<const LinearScanPath>(cands), lsp, space, sel, nbs_test::threads(2));
    INFO(format_selection(s));
    REQUIRE(a.ok());
    CHECK(a.values == b.values);
    CHECK(a.best == b.best);
  }
  // Spot checks against the terms used directly.
  WeightedUtility::Setting w;
  w.non_free_voxels = n_v;
  w.omega = modeling_weight(4);
  sel.selection = Selection::ig_quality;
  CHECK(evaluate_selection(std::span<const LinearScanPath>(cands), lsp, space, sel).values ==
        evaluate_candidates(cands, lsp, space, WeightedUtility(w)).values);
  sel.selection = Selection::occlusion_aware;
  CHECK(evaluate_selection(std::span<const LinearScanPath>(cands), lsp, space, sel).values ==
        evaluate_candidates(cands, lsp, space, OcclusionAwareVI()).values);
  sel.selection = Selection::random;
  sel.seed = 5;
  CHECK(evaluate_selection(std::span<const LinearScanPath>(cands), lsp, space, sel).values ==
        evaluate_candidates(cands, lsp, space, RandomSelection({5})).values);
  const auto empty = evaluate_selection(std::span<const LinearScanPath>(), lsp, space, sel);
  CHECK(empty.status == EvaluationStatus::no_candidates);
}
