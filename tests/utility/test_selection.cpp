// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "nbs/planner/utility_policy.hpp"
#include "nbs/utility/selection.hpp"
#include "test_terms_fixtures.hpp"

using namespace nbs;


namespace {
/// A space after three rows of beams (test_terms_fixtures.hpp), a small stripe sensor and three candidates around it
/// (from +x, from −x, from above).
auto three_views() {
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
  return std::tuple{std::move(space), lsp, std::move(cands)};
}
}  // namespace

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
  auto [space, lsp, cands] = three_views();
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

TEST_CASE("SGU: SG plus beta times the unseen surface the beams reach; the map bins and checks its samples",
          "[utility][selection][sgu]") {
  auto [space, lsp, cands] = three_views();
  // Unseen surface of one voxel face in every voxel of the space; g_u counts the unobserved ones a candidate's beams
  // reach, each once. A sample in a voxel the rows' beams crossed (observed free) counts for no candidate.
  const double lv = space.resolution_m();
  std::vector<UnseenSample> unseen;
  for (int x = 0; x < 10; ++x)
    for (int y = 0; y < 10; ++y)
      for (int z = 0; z < 10; ++z) unseen.push_back({Vec3(x + 0.5, y + 0.5, z + 0.5) * lv, lv * lv, 0.02});
  const UnseenSurfaceMap map = UnseenSurfaceMap::build(unseen, space.grid());
  CHECK(map.total() == Approx(1000.0));
  CHECK(map.voxels() == 1000);
  const auto g_u = evaluate_candidates(cands, lsp, space, UnseenSurfaceVI(&map)).values;
  REQUIRE(g_u.size() == 3);
  CHECK(*std::max_element(g_u.begin(), g_u.end()) > 0.0);
  CHECK(*std::min_element(g_u.begin(), g_u.end()) < *std::max_element(g_u.begin(), g_u.end()));
  // Oracle: the distinct unobserved voxels each candidate's beams visit, collected in a set (one face each).
  struct DistinctUnobserved {
    std::set<std::uint64_t> keys;
    void begin_candidate(std::size_t) { keys.clear(); }
    void begin_ray() {}
    void visit(const VoxelVisit& v) {
      if (!v.observed) keys.insert(v.key.pack());
    }
    void end_ray(const RayEnd&) {}
    [[nodiscard]] double value() const { return static_cast<double>(keys.size()); }
  };
  CHECK(g_u == evaluate_candidates(cands, lsp, space, DistinctUnobserved{}).values);
  for (const double g : g_u) CHECK(g <= 1000.0 - 3 * 8);  // the rows' 3 × 8 crossed or hit voxels never count
  const std::vector<UnseenSample> crossed{{Vec3(2.5, 5.5, 5.5) * lv, lv * lv, 0.02}};
  REQUIRE(space.observed(VoxelKey{2, 5, 5}));
  const UnseenSurfaceMap crossed_map = UnseenSurfaceMap::build(crossed, space.grid());
  for (const double g : evaluate_candidates(cands, lsp, space, UnseenSurfaceVI(&crossed_map)).values) CHECK(g == 0.0);
  std::size_t best_u = 0;  // the argmax of g_u per metre, which a huge β makes SGU's choice
  for (std::size_t i = 1; i < cands.size(); ++i)
    if (g_u[i] / (cands[i].length() + 0.05) > g_u[best_u] / (cands[best_u].length() + 0.05)) best_u = i;

  SelectionSetting sel;
  sel.n_scans = 4;
  sel.unseen = unseen;
  sel.selection = Selection::surface_gain;
  const auto sg = evaluate_selection(std::span<const LinearScanPath>(cands), lsp, space, sel).values;
  sel.selection = Selection::surface_gain_unseen;
  sel.options.unseen_weight = 0.0;
  CHECK(evaluate_selection(std::span<const LinearScanPath>(cands), lsp, space, sel).values == sg);
  const double n_v = non_free_voxel_count(space);
  const auto rse = evaluate_candidates(cands, lsp, space, RearSideEntropyVI()).values;
  for (const double beta : {1.0, 1e6}) {
    sel.options.unseen_weight = beta;
    const auto r = evaluate_selection(std::span<const LinearScanPath>(cands), lsp, space, sel);
    for (std::size_t i = 0; i < cands.size(); ++i)
      CHECK(r.values[i] == Approx((rse[i] + beta * g_u[i]) / n_v / (cands[i].length() + 0.05)));
    if (beta > 1.0) CHECK(r.best == best_u);
  }
  sel.options.unseen_min_edge_distance_m = 0.021;  // every sample is nearer its loop's edge: SG's values
  CHECK(evaluate_selection(std::span<const LinearScanPath>(cands), lsp, space, sel).values == sg);
  sel.options.unseen_min_edge_distance_m = 0.02;
  CHECK(evaluate_selection(std::span<const LinearScanPath>(cands), lsp, space, sel).best == best_u);
  // The same on 1 and 2 threads; SelectionUtility reads the samples from the planner's context.
  sel.options.unseen_weight = 16.0;
  const auto one = evaluate_selection(std::span<const LinearScanPath>(cands), lsp, space, sel, nbs_test::threads(1));
  CHECK(one.values == evaluate_selection(std::span<const LinearScanPath>(cands), lsp, space, sel, nbs_test::threads(2)).values);
  SelectionUtility su;
  su.setting.selection = Selection::surface_gain_unseen;
  su.setting.options = sel.options;
  UtilityContext ctx;
  ctx.scans = 4;
  ctx.unseen_surface = unseen;
  const Parameters defaults;
  ctx.params = &defaults;
  CHECK(su.evaluate(std::span<const LinearScanPath>(cands), lsp, space, ctx, nbs_test::threads(2)).values == one.values);
  sel.unseen = {};  // nothing reported: SG's values
  CHECK(evaluate_selection(std::span<const LinearScanPath>(cands), lsp, space, sel).values == sg);

  // Bad samples are errors naming the value; several samples in one voxel add up; out-of-range ones are skipped.
  const VoxelGrid grid(0.005);
  const std::vector<UnseenSample> nan_pos{{Vec3(std::nan(""), 0, 0), 1e-5}};
  CHECK_THROWS_WITH(UnseenSurfaceMap::build(nan_pos, grid), nbs_test::Contains("not finite"));
  const std::vector<UnseenSample> negative{{Vec3::Zero(), -1e-5}};
  CHECK_THROWS_WITH(UnseenSurfaceMap::build(negative, grid), nbs_test::Contains("area must be finite and >= 0"));
  const std::vector<UnseenSample> two{{Vec3(0.001, 0.001, 0.001), 1e-5, 0.004}, {Vec3(0.004, 0.002, 0.003), 1.5e-5, 0.01},
                                      {Vec3(1e9, 0, 0), 1.0, 0.01}};
  const UnseenSurfaceMap m2 = UnseenSurfaceMap::build(two, grid);
  CHECK(m2.voxels() == 1);
  CHECK(m2.at(VoxelKey{0, 0, 0}) == Approx(1.0));
  CHECK(m2.at(VoxelKey{1, 0, 0}) == 0.0);
  CHECK(UnseenSurfaceMap::build(two, grid, 0.005).at(VoxelKey{0, 0, 0}) == Approx(0.6));  // the first is too near
  CHECK_THROWS_WITH(UnseenSurfaceMap::build(two, grid, -0.001), nbs_test::Contains("min_edge_distance_m"));
  CHECK_THROWS_AS(UnseenSurfaceMap::build(two, grid, std::nan("")), InvalidArgument);
  const std::vector<UnseenSample> nan_d{{Vec3::Zero(), 1e-5, std::nan("")}};
  CHECK_THROWS_WITH(UnseenSurfaceMap::build(nan_d, grid), nbs_test::Contains("edge distance"));
  sel.options.unseen_weight = -1.0;
  CHECK_THROWS_AS(evaluate_selection(std::span<const LinearScanPath>(cands), lsp, space, sel), InvalidArgument);
}
