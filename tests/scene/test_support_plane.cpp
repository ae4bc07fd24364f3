// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <algorithm>
#include <random>

#include "nbs/scene/segmentation.hpp"
#include "nbs/scene/support_plane.hpp"
#include "nbs_random.hpp"

using namespace nbs;
using namespace nbs::scene;

namespace {
/// 7000 points on the plane through (0.1, −0.2, 0.75) with normal n (±1 mm uniform noise) and 3000 uniform outliers
/// in a 1 m cube around it (30 %), shuffled.
std::vector<Vec3> plane_with_outliers(const Vec3& n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-0.5, 0.5), e(-0.001, 0.001);
  const Vec3 c(0.1, -0.2, 0.75);
  const Vec3 a = n.unitOrthogonal(), b = n.cross(a);
  std::vector<Vec3> p;
  for (int i = 0; i < 7000; ++i) {
    const double s = u(rng), t = u(rng);
    p.push_back(c + s * a + t * b + e(rng) * n);
  }
  for (int i = 0; i < 3000; ++i) p.push_back(c + nbs_test::random_vec3(u, rng));
  std::shuffle(p.begin(), p.end(), rng);
  return p;
}
}  // namespace

TEST_CASE("fit_support_plane: a tilted plane with 30 % outliers", "[scene][plane]") {
  const Vec3 n = Vec3(std::sin(0.2), 0.0, std::cos(0.2));  // 11.5 deg tilt
  const std::vector<Vec3> p = plane_with_outliers(n, 7);
  PlaneSettings s;
  s.distance_threshold_m = 0.003;
  const PlaneFit fit = fit_support_plane(p, s);
  REQUIRE(fit.found);
  const double angle = std::acos(std::min(1.0, fit.plane.normal.dot(n)));
  CHECK(angle < 0.5 * std::numbers::pi / 180.0);  // within 0.5 deg
  const Vec3 c(0.1, -0.2, 0.75);
  CHECK(std::abs(fit.plane.signed_distance(c)) < 0.001);  // offset within 1 mm
  std::printf("plane with 30 %% outliers: normal error %.4f deg, offset error %.4f mm, %zu inliers\n",
              angle * 180.0 / std::numbers::pi, 1e3 * std::abs(fit.plane.signed_distance(c)), fit.inliers.size());
  CHECK(fit.inliers.size() >= 7000);   // every plane point, plus the outliers that fall into the band
  CHECK(fit.inliers.size() <= 7200);
  // Deterministic for the seed.
  const PlaneFit again = fit_support_plane(p, s);
  CHECK(again.inliers == fit.inliers);
  CHECK(again.plane.normal == fit.plane.normal);
}

TEST_CASE("fit_support_plane: bad input and no plane", "[scene][plane]") {
  PlaneSettings s;
  CHECK_THROWS_WITH(fit_support_plane(std::vector<Vec3>{}, s), nbs_test::Contains("empty"));
  std::vector<Vec3> p = plane_with_outliers(Vec3::UnitZ(), 1);
  p[17].y() = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_WITH(fit_support_plane(p, s), nbs_test::Contains("point 17"));
  s.iterations = 0;
  CHECK_THROWS_WITH(fit_support_plane(plane_with_outliers(Vec3::UnitZ(), 1), s),
                    nbs_test::Contains("PlaneSettings.iterations"));
  s = {};
  s.distance_threshold_m = -1.0;
  CHECK_THROWS_WITH(fit_support_plane(plane_with_outliers(Vec3::UnitZ(), 1), s),
                    nbs_test::Contains("distance_threshold_m"));
  // A vertical wall only: no support plane within max_tilt_rad; segment_scene reports no_plane.
  const std::vector<Vec3> wall = plane_with_outliers(Vec3::UnitX(), 2);
  const PlaneFit none = fit_support_plane(wall, PlaneSettings{});
  CHECK_FALSE(none.found);
  CHECK_FALSE(none.message.empty());
  const Segmentation seg = segment_scene(wall, SegmentationSettings{});
  CHECK(seg.status == SegmentationStatus::no_plane);
  CHECK(seg.objects.empty());
}

TEST_CASE("segment_scene: two boxes on a table, points below it removed", "[scene][segmentation]") {
  // Table z = 0.7 on a 2 mm grid over 0.4 x 0.4 m; two box tops (3 cm high, 4 cm wide) on a 2 mm grid; 200 points
  // under the table.
  std::vector<Vec3> p;
  for (int i = 0; i < 200; ++i)
    for (int j = 0; j < 200; ++j) p.push_back(Vec3(-0.2 + 0.002 * i, -0.2 + 0.002 * j, 0.7));
  for (const Vec3& c : {Vec3(-0.1, 0.0, 0.73), Vec3(0.1, 0.05, 0.73)})
    for (int i = 0; i <= 20; ++i)
      for (int j = 0; j <= 20; ++j) p.push_back(c + Vec3(-0.02 + 0.002 * i, -0.02 + 0.002 * j, 0.0));
  for (int i = 0; i < 200; ++i) p.push_back(Vec3(0.001 * i - 0.1, 0.0, 0.6));
  SegmentationSettings s;
  const Segmentation seg = segment_scene(p, s);
  REQUIRE(seg.status == SegmentationStatus::ok);
  CHECK(seg.removed_points == 40000 + 200);
  REQUIRE(seg.objects.size() == 2);
  for (const ObjectHypothesis& h : seg.objects) {
    CHECK(h.indices.size() == 441);
    CHECK(h.box.min.z() == Approx(0.7).margin(1e-9));  // standing on the plane
    CHECK(h.box.max.z() == Approx(0.73 + s.box_margin_m).margin(1e-9));
    CHECK(h.box.extent().x() == Approx(0.04 + 2 * s.box_margin_m).margin(1e-9));
    CHECK(h.centroid.z() == Approx(0.73).margin(1e-9));
  }
  CHECK(seg.objects[0].centroid.x() == Approx(-0.1).margin(1e-9));
  // Bad input names the value.
  s.box_margin_m = -0.01;
  CHECK_THROWS_WITH(segment_scene(p, s), nbs_test::Contains("box_margin_m"));
  s = {};
  s.cluster.min_size = 0;
  CHECK_THROWS_WITH(segment_scene(p, s), nbs_test::Contains("min_size"));
  p[5].z() = std::numeric_limits<double>::infinity();
  CHECK_THROWS_WITH(segment_scene(p, SegmentationSettings{}), nbs_test::Contains("point 5"));
  CHECK_THROWS_WITH(segment_scene(std::vector<Vec3>{}, SegmentationSettings{}), nbs_test::Contains("empty"));
}

TEST_CASE("split_hypothesis: what is kept of a cluster, clustered again, with make_hypothesis' boxes",
          "[scene][segmentation]") {
  // Table z = 0 (2 mm grid, 0.3 x 0.3 m); two 4 cm box tops at z = 0.03 that touch (x in [-0.04, 0] and (0, 0.04]):
  // one cluster. Dropping the left top leaves the right one; dropping a 2 cm strip across the right top as well
  // leaves two pieces of it.
  std::vector<Vec3> p;
  for (int i = 0; i <= 150; ++i)
    for (int j = 0; j <= 150; ++j) p.push_back(Vec3(-0.15 + 0.002 * i, -0.15 + 0.002 * j, 0.0));
  for (int i = 0; i <= 40; ++i)
    for (int j = 0; j <= 20; ++j) p.push_back(Vec3(-0.04 + 0.002 * i, -0.02 + 0.002 * j, 0.03));
  const SegmentationSettings s;
  const Segmentation seg = segment_scene(p, s);
  REQUIRE(seg.status == SegmentationStatus::ok);
  REQUIRE(seg.objects.size() == 1);
  const ObjectHypothesis& h = seg.objects[0];
  REQUIRE(h.points.size() == 41 * 21);
  const auto right = [&](std::size_t k) { return h.points[k].x() > 0.001; };
  const std::vector<ObjectHypothesis> one = split_hypothesis(p, h, right, seg.plane.plane, s);
  REQUIRE(one.size() == 1);
  CHECK(one[0].points.size() == 20 * 21);
  CHECK(one[0].box.min.x() == Approx(0.002 - s.box_margin_m).margin(1e-9));
  CHECK(one[0].box.min.z() == Approx(0.0).margin(1e-9));
  CHECK(one[0].box.max.z() == Approx(0.03 + s.box_margin_m).margin(1e-9));
  for (std::size_t k = 0; k < one[0].indices.size(); ++k) CHECK(p[one[0].indices[k]] == one[0].points[k]);
  // The hypothesis of the same indices is the same.
  const ObjectHypothesis again = make_hypothesis(p, one[0].indices, seg.plane.plane, s);
  CHECK(again.box.min == one[0].box.min);
  CHECK(again.box.max == one[0].box.max);
  CHECK((again.centroid - Vec3(0.021, 0.0, 0.03)).norm() < 1e-9);
  const auto pieces = split_hypothesis(
      p, h, [&](std::size_t k) { return right(k) && std::abs(h.points[k].x() - 0.02) > 0.011; }, seg.plane.plane, s);
  REQUIRE(pieces.size() == 2);
  CHECK(pieces[0].centroid.x() < pieces[1].centroid.x());
  CHECK(pieces[0].points.size() + pieces[1].points.size() == (4 + 5) * 21);
  // Nothing kept: no hypothesis; bad members are refused.
  CHECK(split_hypothesis(p, h, [](std::size_t) { return false; }, seg.plane.plane, s).empty());
  CHECK_THROWS_WITH(make_hypothesis(p, std::vector<std::size_t>{}, seg.plane.plane, s), nbs_test::Contains("no member"));
  CHECK_THROWS_WITH(make_hypothesis(p, std::vector<std::size_t>{p.size()}, seg.plane.plane, s),
                    nbs_test::Contains("outside the cloud"));
}
