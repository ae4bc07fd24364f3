// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <set>
#include <vector>

#include "nbs/space/probabilistic_voxel_space.hpp"
#include "nbs/space/ray_traversal.hpp"
#include "nbs/utility/evaluate_candidates.hpp"
#include "nbs/utility/peer_terms.hpp"
#include "nbs/utility/thesis_terms.hpp"
#include "test_terms_fixtures.hpp"
#include "entropy_oracle.hpp"

using namespace nbs;

namespace {

using nbs_test::H;

LaserStripeProfiler small_lsp() {
  LaserStripeProfiler lsp;
  lsp.points_per_profile = 9;
  lsp.fan_angle_rad = 0.4;
  lsp.range = {0.005, 0.3};
  lsp.profile_spacing_m = 0.01;
  return lsp;
}

// A space whose slab x ∈ [0, 0.06) is well known free (5 scans), x = 6 occupied, the rest unknown.
nbs_test::LogOddsSpace slab_space() {
  auto space = nbs_test::make_space();
  std::vector<std::pair<int, int>> rows;
  for (int y = 0; y < 10; ++y)
    for (int z = 0; z < 10; ++z) rows.push_back({y, z});
  for (int k = 0; k < 5; ++k) space.integrate(nbs_test::rows_scan(rows, 6));
  return space;
}

using nbs_test::oracle_entropy_sum;
using nbs_test::ring_candidates;

}  // namespace

TEST_CASE("evaluation matches a brute-force entropy oracle", "[utility][evaluation]") {
  const auto space = slab_space();
  const auto lsp = small_lsp();
  const auto cands = ring_candidates(4);
  const double n_v = non_free_voxel_count(space);
  const auto res = evaluate_candidates(cands, lsp, space, VolumetricEntropy({n_v, true}), nbs_test::threads(1));
  REQUIRE(res.ok());
  for (std::size_t i = 0; i < cands.size(); ++i) {
    std::vector<Ray> rays;
    append_candidate_rays(cands[i], lsp, {}, rays);
    CHECK(res.rays[i] == rays.size());
    CHECK(res.values[i] * n_v == Approx(oracle_entropy_sum(space, rays)).epsilon(1e-9));
  }
}

TEST_CASE("each voxel counts once per candidate, again for the next candidate", "[utility][evaluation]") {
  const auto space = nbs_test::make_space();  // all unknown: entropy 1 per voxel
  LaserStripeProfiler lsp = small_lsp();
  lsp.points_per_profile = 1;  // one ray along +z per profile
  // Two profiles 0 m apart is impossible; a zero-length path gives one profile. Evaluate the same path twice as
  // two candidates: both must see the same 10 unknown voxels.
  const Viewpoint v = Viewpoint::look_at(Vec3(0.055, 0.055, -0.05), Vec3(0.055, 0.055, 0.5), Vec3::UnitX());
  const std::vector<LinearScanPath> cands{LinearScanPath(v), LinearScanPath(v)};
  const auto once = evaluate_candidates(cands, lsp, space, VolumetricEntropy(), nbs_test::threads(1));
  CHECK(once.values[0] == 10.0);
  CHECK(once.values[1] == 10.0);
  // A path along +x over 2 cm with 1 cm spacing: 3 profiles, 3 distinct columns of 10 voxels each.
  const std::vector<LinearScanPath> moving{LinearScanPath(v, v.position() + Vec3(0.02, 0, 0))};
  CHECK(evaluate_candidates(moving, lsp, space, VolumetricEntropy(), nbs_test::threads(1)).values[0] == 30.0);
  // The sub-sampled profiles: every 2nd profile → profiles 0 and 2.
  EvaluationSetting sub;
  sub.sampling.profile_stride = 2;
  CHECK(evaluate_candidates(moving, lsp, space, VolumetricEntropy(), sub).values[0] == 20.0);
  // A path along the beam revisits the same column: counted once, 10 voxels; without the marking, 3 × 10.
  const std::vector<LinearScanPath> along{LinearScanPath(v, v.position() + Vec3(0, 0, 0.02))};
  const auto a1 = evaluate_candidates(along, lsp, space, VolumetricEntropy(), nbs_test::threads(1));
  CHECK(a1.values[0] == 10.0);
  CHECK(a1.voxels[0] == 30u);
  CHECK(evaluate_candidates(along, lsp, space, VolumetricEntropy({1.0, false}), nbs_test::threads(1)).values[0] == 30.0);
}

TEST_CASE("1, 2 and 3 threads give identical values and the same best", "[utility][evaluation]") {
  const auto space = slab_space();
  const auto lsp = small_lsp();
  const auto cands = ring_candidates(7);
  const WeightedUtility term(WeightedUtility::thesis(non_free_voxel_count(space), 3));
  const auto r1 = evaluate_candidates(cands, lsp, space, term, nbs_test::threads(1));
  const auto r2 = evaluate_candidates(cands, lsp, space, term, nbs_test::threads(2));
  const auto r3 = evaluate_candidates(cands, lsp, space, term, nbs_test::threads(3));
  REQUIRE(r1.ok());
  CHECK(r1.values == r2.values);
  CHECK(r1.values == r3.values);
  CHECK(r1.best == r2.best);
  CHECK(r1.best == r3.best);
  CHECK(r2.threads == 2);
  CHECK(r1.best == best_index(r1.values));
  CHECK(r1.t_nbs_s >= 0.0);
  const auto rnd1 = evaluate_candidates(cands, lsp, space, RandomSelection({9}), nbs_test::threads(1));
  const auto rnd2 = evaluate_candidates(cands, lsp, space, RandomSelection({9}), nbs_test::threads(2));
  CHECK(rnd1.values == rnd2.values);
  CHECK(rnd1.best == rnd2.best);
  CHECK(rnd1.rays[0] == 0u);  // Random casts no rays
}

TEST_CASE("IG prefers a view of unknown space over a view of free space", "[utility][evaluation]") {
  const auto space = slab_space();
  REQUIRE(space.probability(VoxelKey{2, 5, 5}) < 0.2);
  AreaSensor cam;
  cam.width_px = 6;
  cam.height_px = 4;
  cam.horizontal_fov_rad = 0.2;
  cam.vertical_fov_rad = 0.2;
  cam.range = {0.001, 0.04};
  // Both look along +y from inside the box, one in the free slab (x = 0.03), one in unknown space (x = 0.08).
  const Viewpoint in_free = Viewpoint::look_at(Vec3(0.03, 0.03, 0.05), Vec3(0.03, 1.0, 0.05));
  const Viewpoint in_unknown = Viewpoint::look_at(Vec3(0.08, 0.03, 0.05), Vec3(0.08, 1.0, 0.05));
  const std::vector<LinearScanPath> cands{LinearScanPath(in_free), LinearScanPath(in_unknown)};
  WeightedUtility::Setting ig;
  ig.non_free_voxels = non_free_voxel_count(space);
  ig.omega = 0.0;
  const auto r = evaluate_candidates(cands, cam, space, WeightedUtility(ig), nbs_test::threads(2));
  REQUIRE(r.ok());
  CHECK(r.best == 1);
  CHECK(r.values[1] > 1.5 * r.values[0]);
}

TEST_CASE("ties go to the lower index; NaN is never chosen", "[utility][evaluation]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK(best_index(std::vector<double>{1.0, 2.0, 2.0}) == 1);
  CHECK(best_index(std::vector<double>{nan, 0.5, nan}) == 1);
  CHECK(best_index(std::vector<double>{nan}) == EvaluationResult::npos);
  CHECK(best_index(std::vector<double>{}) == EvaluationResult::npos);
}

TEST_CASE("bad input: empty list, invalid sensor or sampling, non-finite paths", "[utility][evaluation]") {
  const auto space = nbs_test::make_space();
  auto lsp = small_lsp();
  const std::vector<LinearScanPath> none;
  const auto r = evaluate_candidates(none, lsp, space, VolumetricEntropy());
  CHECK(r.status == EvaluationStatus::no_candidates);
  CHECK(!r.ok());
  CHECK(r.best == EvaluationResult::npos);
  CHECK(r.values.empty());

  const auto cands = ring_candidates(2);
  EvaluationSetting bad;
  bad.sampling.ray_stride = 0;
  CHECK_THROWS_AS(evaluate_candidates(cands, lsp, space, VolumetricEntropy(), bad), InvalidArgument);
  lsp.points_per_profile = 0;
  CHECK_THROWS_AS(evaluate_candidates(cands, lsp, space, VolumetricEntropy()), InvalidArgument);

  // A NaN path cannot be built: the core types reject it before evaluation.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_AS(LinearScanPath(Viewpoint(), Vec3(nan, 0, 0)), InvalidArgument);
  Pose p = Pose::Identity();
  p.translation().x() = nan;
  CHECK_THROWS_AS(Viewpoint(p), InvalidArgument);

  // Huge strides are safe (first profile / ray only); a candidate far outside the box sees nothing.
  EvaluationSetting huge;
  huge.sampling = {std::numeric_limits<std::size_t>::max(), std::numeric_limits<std::size_t>::max()};
  const auto h = evaluate_candidates(cands, small_lsp(), space, VolumetricEntropy(), huge);
  CHECK(h.rays[0] == 1u);
  const Viewpoint far = Viewpoint::look_at(Vec3(100, 100, 100), Vec3(200, 200, 200));
  const auto f = evaluate_candidates(std::vector<LinearScanPath>{LinearScanPath(far)}, small_lsp(), space,
                                     VolumetricEntropy());
  CHECK(f.values[0] == 0.0);
  CHECK(f.voxels[0] == 0u);
  CHECK(f.best == 0);
}

// ---- The evaluator's snapshot path (detail/planning_snapshot.hpp) against space.cast_ray ---------------------------
namespace {

// A VoxelSpace that forwards to another space but reports an empty bounds_keys(), so the evaluator cannot snapshot it
// and takes the space.cast_ray path with per-voxel lookups.
template <class Space>
struct CastRayOnly {
  using State = typename Space::State;
  std::shared_ptr<Space> own;
  const Space* s;
  CastRayOnly(double resolution_m, const Aabb& box) : own(std::make_shared<Space>(resolution_m, box)), s(own.get()) {}
  explicit CastRayOnly(const Space* space) : s(space) {}
  IntegrationStats integrate(const Scan& scan) { return own->integrate(scan); }
  template <class V>
  RaycastResult cast_ray(const Ray& r, V&& v) const {
    return s->cast_ray(r, static_cast<V&&>(v));
  }
  template <class F>
  void for_each(F&& f) const {
    s->for_each(static_cast<F&&>(f));
  }
  [[nodiscard]] const auto& model() const { return s->model(); }
  [[nodiscard]] State state(const VoxelKey& k) const { return s->state(k); }
  [[nodiscard]] double probability(const VoxelKey& k) const { return s->probability(k); }
  [[nodiscard]] double probability(const Vec3& x) const { return s->probability(x); }
  [[nodiscard]] bool occupied(const VoxelKey& k) const { return s->occupied(k); }
  [[nodiscard]] bool observed(const VoxelKey& k) const { return s->observed(k); }
  [[nodiscard]] const VoxelGrid& grid() const { return s->grid(); }
  [[nodiscard]] double resolution_m() const { return s->resolution_m(); }
  [[nodiscard]] const Aabb& bounds() const { return s->bounds(); }
  [[nodiscard]] const Aabb& voxel_bounds() const { return s->voxel_bounds(); }
  [[nodiscard]] KeyBox bounds_keys() const { return {}; }
};

// Records every call (one thread only).
struct Recorder {
  struct Log {
    std::vector<VoxelVisit> visits;
    std::vector<RayEnd> ends;
  };
  Log* log = nullptr;
  void begin_candidate(std::size_t) {}
  void begin_ray() {}
  void visit(const VoxelVisit& v) { log->visits.push_back(v); }
  void end_ray(const RayEnd& e) { log->ends.push_back(e); }
  [[nodiscard]] double value() const { return 0.0; }
};

void check_same_visits(const Recorder::Log& a, const Recorder::Log& b) {
  REQUIRE(a.visits.size() == b.visits.size());
  REQUIRE(a.ends.size() == b.ends.size());
  for (std::size_t i = 0; i < a.ends.size(); ++i) {
    CHECK(a.ends[i].hit == b.ends[i].hit);
    CHECK(a.ends[i].voxels == b.ends[i].voxels);
  }
  std::size_t bad = 0;
  for (std::size_t i = 0; i < a.visits.size(); ++i) {
    const VoxelVisit &x = a.visits[i], &y = b.visits[i];
    const bool same = x.key == y.key && x.probability == y.probability && x.entropy() == y.entropy() &&
                      x.observed == y.observed && x.occupied == y.occupied && x.first_visit == y.first_visit &&
                      x.features == y.features && x.direction == y.direction && x.distance_m == y.distance_m &&
                      x.index == y.index;
    bad += same ? 0 : 1;
  }
  CHECK(bad == 0);
}

// A ThesisModel space over keys 0..9 with the slab pattern of slab_space() plus a few voxels made occupied, some of
// them with surface features.
// The surface features of thesis_slab_space() (what a planner keeps beside its space).
SurfaceFeatureMap& slab_features() {
  static SurfaceFeatureMap features;
  return features;
}

// nbs_test::threads(n) reading slab_features().
EvaluationSetting ft(unsigned n) {
  EvaluationSetting e = nbs_test::threads(n);
  e.features = &slab_features();
  return e;
}

ProbabilisticVoxelSpace<> thesis_slab_space() {
  slab_features() = SurfaceFeatureMap{};
  Aabb box;
  box.min = Vec3::Zero();
  box.max = Vec3::Constant(0.0999);
  ThesisModel::Setting ms;
  ms.sigma_m = [](double) { return 0.002; };
  ms.similar_direction_cells = -1;
  ProbabilisticVoxelSpace<> space(0.01, box, ThesisModel(ms));
  std::vector<std::pair<int, int>> rows;
  for (int y = 0; y < 10; ++y)
    for (int z = 0; z < 10; ++z)
      if ((y + z) % 3 != 0) rows.push_back({y, z});
  for (int k = 0; k < 4; ++k) space.integrate(nbs_test::rows_scan(rows, 5 + (k % 2)));
  SurfaceFeatures f;
  f.mean_density = 0.25f;
  f.border_share = 0.5f;
  f.mean_normal = Eigen::Vector3f(-0.8f, 0.0f, 0.0f);
  int with_features = 0;
  space.for_each([&](const VoxelKey& k, const ThesisState& s) {
    if (space.model().occupied(s) && (k.y + k.z) % 2 == 0) {
      slab_features().set(k, f);
      ++with_features;
    }
  });
  REQUIRE(with_features > 0);
  return space;
}

std::vector<LinearScanPath> mixed_candidates() {
  auto c = ring_candidates(6);
  // Starting inside the box, along an axis, and looking through a box corner.
  c.emplace_back(Viewpoint::look_at(Vec3(0.05, 0.05, 0.05), Vec3(0.5, 0.05, 0.05)), Vec3(0.05, 0.07, 0.05));
  c.emplace_back(Viewpoint::look_at(Vec3(-0.1, -0.1, -0.1), Vec3(0.1, 0.1, 0.1)));
  c.emplace_back(Viewpoint::look_at(Vec3(0.105, 0.05, 0.05), Vec3(0.0, 0.05, 0.05)), Vec3(0.105, 0.05, 0.08));
  return c;
}

template <class Space>
void check_snapshot_matches_cast_ray(const Space& space) {
  auto lsp = small_lsp();
  lsp.points_per_profile = 33;
  const auto cands = mixed_candidates();
  REQUIRE(detail::PlanningSnapshot<Space>(space).enabled());
  for (const RaySampling sampling : {RaySampling{1, 1}, RaySampling{2, 3}}) {
    Recorder::Log fast, slow;
    EvaluationSetting es = ft(1);
    es.sampling = sampling;
    const auto rf = evaluate_candidates(cands, lsp, space, Recorder{&fast}, es);
    const auto rs = evaluate_candidates(cands, lsp, CastRayOnly<Space>{&space}, Recorder{&slow}, es);
    CHECK(rf.voxels == rs.voxels);
    CHECK(rf.rays == rs.rays);
    check_same_visits(fast, slow);
    CHECK(!fast.visits.empty());
  }
}

}  // namespace

TEST_CASE("the snapshot path feeds the same visits as space.cast_ray (log-odds and thesis models)",
          "[utility][evaluation]") {
  SECTION("log-odds slab") { check_snapshot_matches_cast_ray(slab_space()); }
  SECTION("thesis model with features") {
    const auto space = thesis_slab_space();
    check_snapshot_matches_cast_ray(space);
    // Some recorded visits carry features, some hit, some are unobserved: the comparison covered every field.
    Recorder::Log log;
    auto lsp = small_lsp();
    (void)evaluate_candidates(mixed_candidates(), lsp, space, Recorder{&log}, ft(1));
    std::size_t with_f = 0, hits = 0, unobserved = 0, repeats = 0;
    for (const auto& v : log.visits) {
      with_f += v.features != nullptr;
      hits += v.occupied;
      unobserved += !v.observed;
      repeats += !v.first_visit;
    }
    CHECK(with_f > 0);
    CHECK(hits > with_f);
    CHECK(unobserved > 0);
    CHECK(repeats > 0);
  }
}

namespace {
// A Recorder that declares that it ignores repeated visits (visits_first_only).
struct FirstOnlyRecorder : Recorder {
  [[nodiscard]] bool first_visits_only() const { return true; }
};
}  // namespace

TEST_CASE("a term that ignores repeated visits gets exactly the first visits of space.cast_ray, fields unchanged",
          "[utility][evaluation]") {
  CHECK(visits_first_only(FirstOnlyRecorder{}));
  CHECK(!visits_first_only(Recorder{}));
  CHECK(visits_first_only(WeightedUtility()));
  CHECK(visits_first_only(VolumetricEntropy()));
  CHECK(!visits_first_only(VolumetricEntropy({1.0, false})));
  CHECK(!visits_first_only(WeightedUtility({1.0, 0.5, 0.7, 1.0, false})));
  CHECK(!visits_first_only(OcclusionAwareVI()));
  CHECK(visits_first_only(TermSet<VolumetricEntropy, SurfaceQuality>()));
  CHECK(!visits_first_only(TermSet<VolumetricEntropy, OcclusionAwareVI>()));
  const auto space = thesis_slab_space();
  auto lsp = small_lsp();
  lsp.points_per_profile = 33;
  for (const RaySampling sampling : {RaySampling{1, 1}, RaySampling{2, 3}}) {
    Recorder::Log fast, slow;
    EvaluationSetting es = ft(1);
    es.sampling = sampling;
    FirstOnlyRecorder f;
    f.log = &fast;
    const auto rf = evaluate_candidates(mixed_candidates(), lsp, space, f, es);
    const auto rs = evaluate_candidates(mixed_candidates(), lsp, CastRayOnly<ProbabilisticVoxelSpace<>>{&space},
                                        Recorder{&slow}, es);
    CHECK(rf.voxels == rs.voxels);
    CHECK(rf.rays == rs.rays);
    Recorder::Log firsts = slow;
    std::erase_if(firsts.visits, [](const VoxelVisit& v) { return !v.first_visit; });
    CHECK(firsts.visits.size() < slow.visits.size());  // repeated visits existed and were skipped
    check_same_visits(fast, firsts);
  }
}

TEST_CASE("thesis terms give bit-identical values through the snapshot and through space.cast_ray",
          "[utility][evaluation]") {
  const auto space = thesis_slab_space();
  const auto lsp = small_lsp();
  const auto cands = mixed_candidates();
  const double n_v = non_free_voxel_count(space);
  using Slow = CastRayOnly<ProbabilisticVoxelSpace<>>;
  for (double omega : {0.0, 0.4, 1.0}) {
    WeightedUtility::Setting ws;
    ws.non_free_voxels = n_v;
    ws.omega = omega;
    const WeightedUtility term(ws);
    const auto fast = evaluate_candidates(cands, lsp, space, term, ft(2));
    const auto slow = evaluate_candidates(cands, lsp, Slow{&space}, term, ft(1));
    CHECK(fast.values == slow.values);
    CHECK(fast.best == slow.best);
  }
  const auto oa = evaluate_candidates(cands, lsp, space, OcclusionAwareVI(), ft(3));
  const auto oa_slow = evaluate_candidates(cands, lsp, Slow{&space}, OcclusionAwareVI(), ft(1));
  CHECK(oa.values == oa_slow.values);
}

TEST_CASE("a space without a bounded unknown area is evaluated without a snapshot", "[utility][evaluation]") {
  nbs_test::LogOddsSpace unbounded(0.01);
  std::vector<std::pair<int, int>> rows{{5, 5}, {5, 6}, {6, 5}};
  unbounded.integrate(nbs_test::rows_scan(rows, 6));
  CHECK(!detail::PlanningSnapshot<nbs_test::LogOddsSpace>(unbounded).enabled());
  const auto lsp = small_lsp();
  const auto cands = ring_candidates(3);
  const auto r = evaluate_candidates(cands, lsp, unbounded, OcclusionAwareVI(), nbs_test::threads(2));
  const auto s = evaluate_candidates(cands, lsp, CastRayOnly<nbs_test::LogOddsSpace>{&unbounded}, OcclusionAwareVI(),
                                     nbs_test::threads(1));
  CHECK(r.values == s.values);
  CHECK(r.values[0] > 0.0);
}

TEST_CASE("precomputed entropy equals voxel_entropy(p); without it VoxelVisit computes it", "[utility][evaluation]") {
  VoxelVisit v;
  v.probability = 0.3;
  CHECK(v.entropy() == voxel_entropy(0.3));
  v.entropy_bits = 0.25;
  CHECK(v.entropy() == 0.25);
}

TEST_CASE("coarse-to-fine: the top k of the coarse pass are re-scored, the best is chosen among them",
          "[utility][evaluation][refine]") {
  const auto space = slab_space();
  const auto lsp = small_lsp();
  const auto cands = ring_candidates(12);
  const WeightedUtility term(WeightedUtility::thesis(non_free_voxel_count(space), 3));
  // Oracle: the two single passes (coarse = strides × 2) and the selection done by hand.
  EvaluationSetting fine_only = nbs_test::threads(1), coarse_only = nbs_test::threads(1);
  coarse_only.sampling = {2, 2};
  const auto fine = evaluate_candidates(cands, lsp, space, term, fine_only);
  const auto coarse = evaluate_candidates(cands, lsp, space, term, coarse_only);
  REQUIRE(fine.values != coarse.values);  // the passes differ, so the mix below is observable
  for (const std::size_t k : {std::size_t{1}, std::size_t{3}, std::size_t{5}}) {
    std::vector<std::size_t> order(cands.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return coarse.values[a] > coarse.values[b]; });
    order.resize(k);
    std::vector<double> want = coarse.values;
    std::size_t want_best = order[0];
    for (std::size_t i : order) {
      want[i] = fine.values[i];
      if (fine.values[i] > fine.values[want_best] || (fine.values[i] == fine.values[want_best] && i < want_best))
        want_best = i;
    }
    CAPTURE(k);
    CHECK(top_indices(coarse.values, k) == order);
    for (const unsigned t : {1u, 2u, 3u}) {
      CAPTURE(t);
      const auto r = evaluate_candidates(cands, lsp, space, term, EvaluationSetting{t, RaySampling{}, CoarseToFine{2, k}});
      REQUIRE(r.ok());
      CHECK(r.values == want);
      CHECK(r.best == want_best);
      for (std::size_t i = 0; i < cands.size(); ++i) {
        const bool in_top = std::find(order.begin(), order.end(), i) != order.end();
        CHECK(r.refined[i] == (in_top ? 1 : 0));
        CHECK(r.rays[i] == (in_top ? fine.rays[i] : coarse.rays[i]));
      }
    }
  }
  // At most refine_top candidates, factor 1, or a term without rays: one pass with the full sampling.
  for (const CoarseToFine off : {CoarseToFine{2, 12}, CoarseToFine{1, 3}}) {
    const auto r = evaluate_candidates(cands, lsp, space, term, EvaluationSetting{1, RaySampling{}, off});
    CHECK(r.values == fine.values);
    CHECK(r.best == fine.best);
    CHECK(r.refined == std::vector<std::uint8_t>(cands.size(), 1));
  }
  const auto rnd = evaluate_candidates(cands, lsp, space, RandomSelection({9}), EvaluationSetting{2, RaySampling{}, CoarseToFine{2, 3}});
  CHECK(rnd.values == evaluate_candidates(cands, lsp, space, RandomSelection({9}), nbs_test::threads(1)).values);
}

TEST_CASE("coarse-to-fine: NaN is never re-scored or chosen; bad settings throw", "[utility][evaluation][refine]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK(top_indices(std::vector<double>{1.0, nan, 3.0, 3.0, 2.0}, 3) == std::vector<std::size_t>{2, 3, 4});
  CHECK(top_indices(std::vector<double>{nan, 1.0}, 5) == std::vector<std::size_t>{1});
  CHECK(top_indices(std::vector<double>{nan}, 1).empty());
  CHECK(CoarseToFine{4, 1}.coarse({3, std::numeric_limits<std::size_t>::max() / 2}).profile_stride == 12);
  CHECK(CoarseToFine{4, 1}.coarse({3, std::numeric_limits<std::size_t>::max() / 2}).ray_stride ==
        std::numeric_limits<std::size_t>::max());
  const auto space = nbs_test::make_space();
  const auto cands = ring_candidates(4);
  CHECK_THROWS_WITH(evaluate_candidates(cands, small_lsp(), space, VolumetricEntropy(),
                                        EvaluationSetting{1, RaySampling{}, CoarseToFine{0, 2}}),
                    nbs_test::Contains("coarse_factor") && nbs_test::Contains("0"));
  CHECK_THROWS_AS(evaluate_candidates(cands, small_lsp(), space, VolumetricEntropy(),
                                      EvaluationSetting{1, RaySampling{}, CoarseToFine{2, 0}}),
                  InvalidArgument);
}
