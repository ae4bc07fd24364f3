// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include <cmath>
#include <numbers>
#include <set>
#include <utility>
#include <vector>

#include "nbs/space/ray_traversal.hpp"
#include "nbs/utility/evaluate_candidates.hpp"
#include "nbs/utility/peer_terms.hpp"
#include "nbs/utility/surface_gain.hpp"
#include "nbs/utility/thesis_terms.hpp"
#include "test_terms_fixtures.hpp"
#include "entropy_oracle.hpp"

using namespace nbs;
using nbs_test::key;

namespace {

using nbs_test::H;

VoxelVisit vv(double p, bool observed, bool occupied, std::uint32_t index, bool first = true) {
  VoxelVisit v;
  v.key = {static_cast<int>(index), 0, 0};
  v.probability = p;
  v.observed = observed;
  v.occupied = occupied;
  v.index = index;
  v.first_visit = first;
  return v;
}

struct HandRay {
  std::vector<VoxelVisit> voxels;
  bool hit;
};

// Ray 1: unknown, free 0.2, unknown, unknown, occupied 0.9 (hit). Ray 2: free 0.3, occupied 0.95 (hit).
// Ray 3: two unknown voxels, no hit.
std::vector<HandRay> hand_rays() {
  return {{{vv(0.5, false, false, 0), vv(0.2, true, false, 1), vv(0.5, false, false, 2), vv(0.5, false, false, 3),
            vv(0.9, true, true, 4)},
           true},
          {{vv(0.3, true, false, 0), vv(0.95, true, true, 1)}, true},
          {{vv(0.5, false, false, 0), vv(0.5, false, false, 1)}, false}};
}

template <class Term>
double feed(Term t, const std::vector<HandRay>& rays) {
  t.begin_candidate(0);
  for (const auto& r : rays) {
    t.begin_ray();
    for (const auto& v : r.voxels) t.visit(v);
    t.end_ray({r.hit, static_cast<std::uint32_t>(r.voxels.size())});
  }
  return t.value();
}

}  // namespace

TEST_CASE("peer VI metrics on hand-built rays (Delmerico et al. 2018)", "[utility][peer]") {
  const auto rays = hand_rays();
  // P_v(x_n) = prod_{i<n} (1 - p_i) along ray 1: 1, 0.5, 0.4, 0.2, 0.1.
  const double oa1 = 1 * H(.5) + .5 * H(.2) + .4 * H(.5) + .2 * H(.5) + .1 * H(.9);
  const double oa2 = 1 * H(.3) + .7 * H(.95);
  const double oa3 = 1 * H(.5) + .5 * H(.5);
  CHECK(feed(OcclusionAwareVI{}, rays) == Approx(oa1 + oa2 + oa3));
  CHECK(feed(UnobservedVoxelVI{}, rays) == Approx((1 + .4 + .2) + 0 + (1 + .5)));
  CHECK(feed(RearSideVoxelVI{}, rays) == 1.0);          // only ray 1 reaches its occupied voxel from unknown space
  CHECK(feed(RearSideEntropyVI{}, rays) == Approx(.4 + .2));  // the unknown run just before the hit of ray 1
  const double all = 5 * H(.5) + H(.2) + H(.9) + H(.3) + H(.95);
  CHECK(feed(AverageEntropyVI{}, rays) == Approx(all / 9));
  CHECK(feed(AverageEntropyVI({false, true}), rays) == Approx((all - 2 * H(.5)) / 7));  // hit rays only
  CHECK(feed(AverageEntropyVI{}, {}) == 0.0);
}

TEST_CASE("count_once skips repeated voxels but keeps visibility", "[utility][peer]") {
  // Same ray twice; the second time every voxel is a repeat.
  auto rays = hand_rays();
  rays.resize(1);
  HandRay again = rays[0];
  for (auto& v : again.voxels) v.first_visit = false;
  rays.push_back(again);
  const double oa1 = 1 * H(.5) + .5 * H(.2) + .4 * H(.5) + .2 * H(.5) + .1 * H(.9);
  CHECK(feed(OcclusionAwareVI{}, rays) == Approx(2 * oa1));
  CHECK(feed(OcclusionAwareVI({true}), rays) == Approx(oa1));
  CHECK(feed(RearSideVoxelVI({true}), rays) == 1.0);
  CHECK(feed(RearSideEntropyVI({true}), rays) == Approx(.6));
  CHECK(feed(VolumetricEntropy{}, rays) == Approx(3 * H(.5) + H(.2) + H(.9)));
  CHECK(feed(VolumetricEntropy({1.0, false}), rays) == Approx(2 * (3 * H(.5) + H(.2) + H(.9))));
}

TEST_CASE("Vasquez-Gomez area factor polynomial", "[utility][peer]") {
  for (double a : {0.2, 0.5, 0.8}) {
    CHECK(vasquez_gomez_area_factor(0.0, a) == Approx(0.0).margin(1e-12));
    CHECK(vasquez_gomez_area_factor(a, a) == Approx(1.0));
    CHECK(vasquez_gomez_area_factor(1.0, a) == Approx(0.0).margin(1e-12));
    CHECK(vasquez_gomez_area_factor(a + 1e-9, a) == Approx(1.0).epsilon(1e-6));  // continuous at α
  }
  // By hand: α = 0.2, x = 0.1: −2·0.001/0.008 + 3·0.01/0.04 = 0.5; x = 0.6: (−0.432 + 1.296 − 0.72 − 0.4)/(−0.512) = 0.5.
  CHECK(vasquez_gomez_area_factor(0.1, 0.2) == Approx(0.5));
  CHECK(vasquez_gomez_area_factor(0.6, 0.2) == Approx(0.5));
  CHECK_THROWS_AS(vasquez_gomez_area_factor(0.5, 1.0), InvalidArgument);
}

TEST_CASE("proximity field, proximity count and Vasquez-Gomez on a space", "[utility][peer]") {
  auto space = nbs_test::make_space();
  space.integrate(nbs_test::rows_scan({{5, 5}}, 7));  // (0..6, 5, 5) free, (7, 5, 5) occupied
  REQUIRE(space.occupied(key(7, 5, 5)));
  const ProximityField field = ProximityField::build(space, 0.015);  // neighbours within 1.5 voxels
  CHECK(field.distance_m(key(8, 5, 5)) == Approx(0.01));
  CHECK(field.distance_m(key(8, 6, 5)) == Approx(0.01 * std::sqrt(2.0)));
  CHECK(field.distance_m(key(8, 6, 6)) < 0.0);   // √3 voxels > 1.5
  CHECK(field.distance_m(key(6, 5, 5)) < 0.0);   // observed
  CHECK(field.distance_m(key(9, 5, 5)) < 0.0);   // 2 voxels away
  // 6 face neighbours minus the observed (6,5,5): 5 at 1 voxel; 12 edge neighbours minus none observed: 12 at √2.
  CHECK(field.size() == 17);

  // Hand rays over that space's keys: ray A crosses (8,5,5) and (9,5,5) unobserved; ray B hits (7,5,5) from free.
  VoxelVisit a0 = vv(0.5, false, false, 0), a1 = vv(0.5, false, false, 1);
  a0.key = key(8, 5, 5);
  a1.key = key(8, 6, 5);
  VoxelVisit b0 = vv(0.4, true, false, 0), b1 = vv(0.7, true, true, 1);
  b0.key = key(6, 5, 5);
  b1.key = key(7, 5, 5);
  VoxelVisit c0 = vv(0.5, false, false, 0);
  c0.key = key(0, 0, 0);
  const std::vector<HandRay> rays{{{a0, a1}, false}, {{b0, b1}, true}, {{c0}, false}};
  CHECK(feed(ProximityCountVI(field), rays) == Approx((0.015 - 0.01) + (0.015 - 0.01 * std::sqrt(2.0))));
  // VG: ray A → occplane, B → occupied, C → unobserved; shares 1/3 each.
  CHECK(feed(VasquezGomezVI(field), rays) ==
        Approx(vasquez_gomez_area_factor(1.0 / 3, 0.2) + vasquez_gomez_area_factor(1.0 / 3, 0.8)));
  CHECK_THROWS_AS(feed(ProximityCountVI{}, rays), InvalidArgument);  // no field
}

TEST_CASE("entropy e_v (Eq. 4.32) against a hand-computed grid", "[utility][thesis]") {
  auto space = nbs_test::make_space();
  space.integrate(nbs_test::rows_scan({{5, 5}, {5, 6}}, 7));
  const double p_free = space.probability(key(3, 5, 5)), p_hit = space.probability(key(7, 5, 5));
  REQUIRE(p_free == Approx(0.4).epsilon(1e-6));
  REQUIRE(p_hit == Approx(0.7).epsilon(1e-6));
  // N_v: 1000 voxels in the box, 14 free (p = 0.4 < 0.5).
  const double n_v = non_free_voxel_count(space);
  CHECK(n_v == 986.0);

  VolumetricEntropy ev({n_v, true});
  ev.begin_candidate(0);
  const auto cast = [&](const Ray& r) {
    ev.begin_ray();
    const RaycastResult res = space.cast_ray(r, [&](const VoxelKey& k, const LogOddsState& s) {
      VoxelVisit v;
      v.key = k;
      v.probability = space.model().probability(s);
      v.first_visit = true;
      ev.visit(v);
      return true;
    });
    ev.end_ray({res.hit, res.voxels});
    return res;
  };
  // Along row (5,5): 7 free voxels and the hit voxel, then the ray stops.
  const RaycastResult r1 = cast({Vec3(-0.05, 0.055, 0.055), Vec3(0.2, 0.055, 0.055)});
  CHECK(r1.hit);
  CHECK(r1.voxels == 8);
  // Along an unknown row: 10 voxels of entropy 1.
  const RaycastResult r2 = cast({Vec3(-0.05, 0.025, 0.035), Vec3(0.2, 0.025, 0.035)});
  CHECK(!r2.hit);
  CHECK(r2.voxels == 10);
  CHECK(ev.sum() == Approx(7 * H(0.4) + H(0.7) + 10));
  CHECK(ev.value() == Approx((7 * H(0.4) + H(0.7) + 10) / 986.0));
}

TEST_CASE("surface modeling part Σ(1 − q_i)/N_v (Eqs. 4.33-4.34): λ, incidence cut-off, normalisation", "[utility][thesis]") {
  const double deg = std::numbers::pi / 180.0;
  SurfaceFeatures f;
  f.border_share = 0.4f;
  f.mean_density = 0.6f;
  const Vec3 ray_dir(1, 0, 0);
  const auto q_for = [&](const Eigen::Vector3f& n, double n_v = 10.0, bool first = true) {
    f.mean_normal = n;
    SurfaceQuality q({n_v, 0.7, 70 * deg, true});
    q.begin_candidate(0);
    q.begin_ray();
    VoxelVisit v;
    v.features = &f;
    v.direction = ray_dir;
    v.first_visit = first;
    q.visit(v);
    v.features = nullptr;  // a voxel without features adds nothing
    q.visit(v);
    q.end_ray({true, 2});
    return q.value();
  };
  const double qi = 1.0 - (0.7 * (1.0 - 0.4f) + 0.3 * 0.6f);  // 1 − q_i, q_i = λ(1 − b_i) + (1 − λ)d̄_i
  CHECK(q_for({-1, 0, 0}) == Approx(qi / 10));                       // head-on, θ = 0
  CHECK(q_for({-0.5f, 0, 0}) == Approx(qi / 10));                    // |n̄| < 1 is normalised
  const auto at = [](double t) { return Eigen::Vector3f(float(-std::cos(t)), float(std::sin(t)), 0); };
  CHECK(q_for(at(69 * deg)) == Approx(qi / 10));
  CHECK(q_for(at(71 * deg)) == 0.0);                                 // θ ≥ 70°
  CHECK(q_for({1, 0, 0}) == 0.0);                                    // back-facing
  CHECK(q_for({0, 0, 0}) == 0.0);                                    // no normal
  CHECK(q_for({-1, 0, 0}, 10.0, false) == 0.0);                      // already counted for this candidate
  CHECK(incidence_angle_rad(ray_dir, at(30 * deg)) == Approx(30 * deg).margin(1e-6));
  CHECK_THROWS_AS(SurfaceQuality({0.0, 0.7, 1.0, true}), InvalidArgument);
  CHECK_THROWS_AS(SurfaceQuality({1.0, 1.5, 1.0, true}), InvalidArgument);
}

TEST_CASE("weighted utility combines e_v and q_s from one cast (Eq. 4.30)", "[utility][thesis]") {
  SurfaceFeatures f;
  f.border_share = 1.0f;
  f.mean_density = 0.5f;
  f.mean_normal = {-1, 0, 0};
  std::vector<VoxelVisit> ray{vv(0.5, false, false, 0), vv(0.4, true, false, 1), vv(0.97, true, true, 2)};
  for (auto& v : ray) v.direction = Vec3(1, 0, 0);
  ray[2].features = &f;
  const double n_v = 4.0;
  const double ev = (H(0.5) + H(0.4) + H(0.97)) / n_v, ms = (1.0 - (0.7 * (1.0 - 1.0) + 0.3 * 0.5)) / n_v;
  for (double n_s : {0.0, 2.0, 5.0, 12.0}) {
    const WeightedUtility w(WeightedUtility::thesis(n_v, n_s));
    const double omega = n_s / (n_s + 5.0);
    CHECK(w.omega() == Approx(omega));
    CHECK(feed(w, {{ray, true}}) == Approx((1 - omega) * ev + omega * ms));
  }
  WeightedUtility::Setting s;
  s.non_free_voxels = n_v;
  s.omega = 0.0;  // IG
  CHECK(feed(WeightedUtility(s), {{ray, true}}) == Approx(ev));
  s.omega = 1.0;  // Quality
  CHECK(feed(WeightedUtility(s), {{ray, true}}) == Approx(ms));
  s.omega = 1.5;
  CHECK_THROWS_AS(WeightedUtility(s), InvalidArgument);
}

TEST_CASE("surface gain SG: rear-side entropy per metre of scan path, optionally with Eq. 4.30's m_s", "[utility][sg]") {
  SurfaceFeatures f;
  f.border_share = 1.0f;
  f.mean_density = 0.5f;
  f.mean_normal = {-1, 0, 0};
  // One ray: unknown, unknown, free, unknown, occupied (features, head-on). The rear-side run is the last unknown
  // voxel only (the free voxel ends the first run): P_v = 1·0.5·0.5·(1 − 0.1) = 0.225 there.
  std::vector<VoxelVisit> ray{vv(0.5, false, false, 0), vv(0.5, false, false, 1), vv(0.1, true, false, 2),
                              vv(0.5, false, false, 3), vv(0.97, true, true, 4)};
  for (auto& v : ray) v.direction = Vec3(1, 0, 0);
  ray[4].features = &f;
  const double n_v = 4.0, g_rs = 0.225 * H(0.5) / n_v, ms = (1.0 - 0.3 * 0.5) / n_v;
  SurfaceGain::Setting s;
  s.non_free_voxels = n_v;
  for (const auto& [modeling, omega] : {std::pair{true, 0.0}, {true, 0.3}, {true, 1.0}, {false, 0.3}, {false, 1.0}}) {
    s.modeling = modeling;
    s.omega = omega;
    const double bracket = modeling ? (1 - omega) * g_rs + omega * ms : g_rs;  // default: no modeling term
    CHECK(feed(SurfaceGain(s), {{ray, true}}) == Approx(bracket));
    const std::vector<double> lengths{0.0, 0.15};  // candidate 0: a single view; 1: a 150 mm path
    SurfaceGain per_metre(s, lengths);
    per_metre.begin_candidate(1);
    per_metre.begin_ray();
    for (const auto& v : ray) per_metre.visit(v);
    per_metre.end_ray({true, 5});
    CHECK(per_metre.value() == Approx(bracket / (0.15 + 0.05)));
    CHECK(feed(SurfaceGain(s, lengths), {{ray, true}}) == Approx(bracket / 0.05));  // candidate 0
  }
  // A short path of equal gain wins; the term's bracket is RearSideEntropyVI / N_v and SurfaceQuality.
  s.modeling = true;
  s.omega = 0.0;
  CHECK(feed(SurfaceGain(s), {{ray, true}}) == Approx(feed(RearSideEntropyVI{}, {{ray, true}}) / n_v));
  const std::vector<double> bad{std::nan("")};
  CHECK_THROWS_AS(SurfaceGain(s, bad), InvalidArgument);
  const std::vector<double> one{0.1};
  SurfaceGain short_list(s, one);
  CHECK_THROWS_AS(short_list.begin_candidate(1), InvalidArgument);  // no length for candidate 1
  s.length_offset_m = 0.0;
  CHECK_THROWS_AS(SurfaceGain(s), InvalidArgument);
  s.length_offset_m = 0.05;
  s.omega = -0.1;
  CHECK_THROWS_AS(SurfaceGain(s), InvalidArgument);
}

TEST_CASE("random selection depends on seed and candidate index only", "[utility][thesis]") {
  RandomSelection a({42}), b({42}), c({43});
  std::set<double> seen;
  for (std::size_t i = 0; i < 50; ++i) {
    a.begin_candidate(i);
    b.begin_candidate(i);
    c.begin_candidate(i);
    CHECK(a.value() == b.value());
    CHECK(a.value() >= 0.0);
    CHECK(a.value() < 1.0);
    seen.insert(a.value());
  }
  CHECK(seen.size() == 50);
  c.begin_candidate(3);
  a.begin_candidate(3);
  CHECK(a.value() != c.value());
}

TEST_CASE("TermSet feeds several terms from one pass", "[utility]") {
  TermSet<OcclusionAwareVI, UnobservedVoxelVI, VolumetricEntropy> set;
  const auto rays = hand_rays();
  const double v = feed(set, rays);
  CHECK(v == Approx(feed(OcclusionAwareVI{}, rays)));
  set.begin_candidate(0);
  for (const auto& r : rays) {
    set.begin_ray();
    for (const auto& x : r.voxels) set.visit(x);
    set.end_ray({r.hit, 0});
  }
  const auto vals = set.values();
  CHECK(vals[1] == Approx(feed(UnobservedVoxelVI{}, rays)));
  CHECK(vals[2] == Approx(feed(VolumetricEntropy{}, rays)));
}
