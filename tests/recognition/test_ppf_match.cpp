// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "nbs/io/load_mesh.hpp"
#include "nbs/mesh/normalize.hpp"
#include "nbs/recognition/ppf_match.hpp"
#include "nbs/sim/surface_samples.hpp"
#include "recognition_scenes.hpp"

using namespace nbs;
using namespace nbs::test;

TEST_CASE("PpfModel: the table holds every ordered pair once, keyed by its feature; deterministic", "[recognition]") {
  const OrientedPoints model = oriented_points(sample_surface(bunny(), 4000, 1));
  const PpfModel m(model);
  const std::size_t n = m.points().size();
  INFO("subsampled model points " << n << ", diameter " << m.diameter_m());
  CHECK(n > 100);
  CHECK(m.quantizer().distance_step_m == Approx(0.05 * m.diameter_m()));
  CHECK(m.pair_count() == n * (n - 1));
  // Every pair is found under its own key, with its own α_m.
  std::size_t found = 0;
  for (std::size_t i = 0; i < n; i += 37)
    for (std::size_t j = 0; j < n; j += 11) {
      if (i == j) continue;
      const auto& p = m.points();
      const auto entries = m.find(m.quantizer().key(point_pair_feature(p.points[i], p.normals[i], p.points[j], p.normals[j])));
      const float alpha = static_cast<float>(pair_angle(m.alignment(i), p.points[i], p.points[j]));
      for (const PpfEntry& e : entries) found += (e.reference == i && e.alpha == alpha);
    }
  std::size_t expected = 0;
  for (std::size_t i = 0; i < n; i += 37)
    for (std::size_t j = 0; j < n; j += 11) expected += (i != j);
  CHECK(found == expected);
  CHECK(m.find(~std::uint64_t{0} - 1).empty());
  const PpfModel again(model);
  REQUIRE(again.key_count() == m.key_count());
  CHECK(again.points().points == m.points().points);
}

TEST_CASE("match_ppf recognises the bunny in partial views at random poses", "[recognition]") {
  const IndexedMesh mesh = bunny();
  const PpfModel model(oriented_points(sample_surface(mesh, 20000, 1)));
  const PpfModel box_model(oriented_points(sample_surface(box_like_bunny(mesh), 20000, 1)));
  const PpfModel sphere_model(oriented_points(sample_surface(sphere_like_bunny(mesh), 20000, 1)));
  double worst_t = 0, worst_r = 0, ms = 0;
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    const PartialView view = partial_view(mesh, seed);
    const auto t0 = std::chrono::steady_clock::now();
    const std::vector<PoseHypothesis> h = match_ppf(model, view.scene);
    ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    REQUIRE(!h.empty());
    const double et = (h[0].pose.translation() - view.truth.translation()).norm();
    const double er = rotation_angle_between(h[0].pose.linear(), view.truth.linear());
    worst_t = std::max(worst_t, et), worst_r = std::max(worst_r, er);
    const std::vector<PoseHypothesis> hb = match_ppf(box_model, view.scene);
    const std::vector<PoseHypothesis> hs = match_ppf(sphere_model, view.scene);
    const double other = std::max(hb.empty() ? 0.0 : hb[0].score, hs.empty() ? 0.0 : hs[0].score);
    std::printf("seed %llu: %zu scene points, top score %.0f (2nd %.0f), box %.0f, sphere %.0f, error %.2f mm %.2f deg\n",
                static_cast<unsigned long long>(seed), view.scene.size(), h[0].score, h.size() > 1 ? h[1].score : 0.0,
                hb.empty() ? 0.0 : hb[0].score, hs.empty() ? 0.0 : hs[0].score, 1e3 * et, er * 180 / 3.14159265358979);
    CHECK(et <= 0.005);
    CHECK(er <= 6.0 * 3.14159265358979 / 180);  // before any ICP: d_angle = 12°, d_dist = 12.8 mm
    CHECK(other <= 0.5 * h[0].score);
  }
  std::printf("worst error %.2f mm %.2f deg; match %.1f ms per view\n", 1e3 * worst_t, worst_r * 180 / 3.14159265358979, ms / 4);
}

TEST_CASE("match_ppf is deterministic", "[recognition]") {
  const IndexedMesh mesh = bunny();
  const PpfModel model(oriented_points(sample_surface(mesh, 6000, 3)));
  const PartialView view = partial_view(mesh, 9);
  const auto a = match_ppf(model, view.scene), b = match_ppf(model, view.scene);
  REQUIRE(a.size() == b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    CHECK(a[i].score == b[i].score);
    CHECK(a[i].pose.matrix() == b[i].pose.matrix());
  }
}

TEST_CASE("PpfModel and match_ppf: bad input names the value", "[recognition]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  OrientedPoints two{{Vec3(0, 0, 0), Vec3(0.1, 0, 0)}, {Vec3::UnitZ(), Vec3::UnitZ()}};
  CHECK_THROWS_WITH(PpfModel(OrientedPoints{}), nbs_test::Contains("no points"));
  CHECK_THROWS_WITH(PpfModel(OrientedPoints{two.points, {}}), nbs_test::Contains("no normals"));
  CHECK_THROWS_WITH(PpfModel(OrientedPoints{two.points, {Vec3::UnitZ()}}), nbs_test::Contains("1 normals for 2 points"));
  OrientedPoints bad = two;
  bad.points[1].y() = nan;
  CHECK_THROWS_WITH(PpfModel(bad), nbs_test::Contains("point 1 is not finite"));
  bad = two;
  bad.normals[0] = Vec3::Zero();
  CHECK_THROWS_WITH(PpfModel(bad), nbs_test::Contains("normal 0 must be a unit vector, its length is 0"));
  bad = two;
  bad.points[1] = bad.points[0];
  CHECK_THROWS_WITH(PpfModel(bad), nbs_test::Contains("diameter is 0"));
  PpfModelSetting s;
  s.distance_step_ratio = 0.0;
  CHECK_THROWS_WITH(PpfModel(two, s), nbs_test::Contains("distance_step_ratio"));
  s = {};
  s.angle_step_rad = nan;
  CHECK_THROWS_WITH(PpfModel(two, s), nbs_test::Contains("angle_step_rad"));
  s = {};
  s.max_points = 1;
  CHECK_THROWS_WITH(PpfModel(two, s), nbs_test::Contains("max_points"));

  const PpfModel m(two);
  CHECK(m.pair_count() == 2);
  CHECK_THROWS_WITH(match_ppf(m, OrientedPoints{}), nbs_test::Contains("scene: no points"));
  bad = two;
  bad.normals[1] = Vec3(nan, 0, 0);
  CHECK_THROWS_WITH(match_ppf(m, bad), nbs_test::Contains("scene: normal 1"));
  PpfMatchSetting ms;
  ms.reference_step = 0;
  CHECK_THROWS_WITH(match_ppf(m, two, ms), nbs_test::Contains("reference_step"));
  ms = {};
  ms.cluster_translation_ratio = -1;
  CHECK_THROWS_WITH(match_ppf(m, two, ms), nbs_test::Contains("cluster_translation_ratio"));
  ms = {};
  ms.cluster_rotation_rad = 0;
  CHECK_THROWS_WITH(match_ppf(m, two, ms), nbs_test::Contains("cluster_rotation_rad"));
  // The model itself as scene: its one pair votes for the identity.
  const auto h = match_ppf(m, two);
  REQUIRE(!h.empty());
  CHECK(h[0].pose.translation().norm() < 1e-9);
}
