// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include <cmath>
#include <numbers>

#include "nbs/sensor/presets.hpp"

using nbs_test::Contains;
using nbs::Vec3;

namespace {
nbs::Pose rotated_pose() {
  nbs::Pose p = nbs::Pose::Identity();
  p.linear() = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  p.translation() = Vec3(0.1, -0.2, 0.3);
  return p;
}
}  // namespace

TEST_CASE("LSP fan: first and last rays at -fan/2 and +fan/2 in the sensor x-z plane", "[sensor][lsp]") {
  nbs::LaserStripeProfiler s = nbs::presets::dlr_lsp();
  s.points_per_profile = 101;
  const nbs::Pose pose = rotated_pose();
  const auto dirs = s.profile_directions(pose);
  REQUIRE(dirs.size() == 101);
  const Vec3 sx = pose.linear().col(0), sy = pose.linear().col(1), sz = pose.linear().col(2);
  const double half = 0.5 * s.fan_angle_rad;
  CHECK(std::atan2(dirs.front().dot(sx), dirs.front().dot(sz)) == Approx(-half));
  CHECK(std::atan2(dirs.back().dot(sx), dirs.back().dot(sz)) == Approx(half));
  CHECK(dirs[50].dot(sz) == Approx(1.0));  // middle ray along the viewing direction
  for (const Vec3& d : dirs) {
    CHECK(d.norm() == Approx(1.0));
    CHECK(std::abs(d.dot(sy)) < 1e-12);  // in the x–z plane
  }
  // Equal angular steps fan/(n−1).
  CHECK(std::acos(dirs[0].dot(dirs[1])) == Approx(s.fan_angle_rad / 100.0));
}

TEST_CASE("LSP profiles along a path: count, spacing, first and last included", "[sensor][lsp]") {
  const nbs::LaserStripeProfiler s = nbs::presets::dlr_lsp();  // 1 mm spacing
  CHECK(s.profile_count(0.0) == 1);
  CHECK(s.profile_count(0.05) == 51);     // exact multiple: 50 gaps
  CHECK(s.profile_count(0.0505) == 52);   // one more gap so that spacing ≤ 1 mm
  CHECK(s.profile_count(0.0009) == 2);
  const auto v = nbs::Viewpoint::look_at({0.3, 0, 0.1}, {0, 0, 0.1});
  const nbs::LinearScanPath path(v, v.position() + 0.0505 * v.y_axis());
  const auto poses = s.profile_poses(path);
  REQUIRE(poses.size() == 52);
  CHECK((poses.front().translation() - path.start().position()).norm() < 1e-15);
  CHECK((poses.back().translation() - path.end_position()).norm() < 1e-15);
  for (std::size_t k = 1; k < poses.size(); ++k) {
    const double step = (poses[k].translation() - poses[k - 1].translation()).norm();
    CHECK(step <= s.profile_spacing_m + 1e-12);
    CHECK(step == Approx(0.0505 / 51));
    CHECK(poses[k].linear().isApprox(v.pose().linear()));
  }
}

TEST_CASE("LSP presets follow Tab. 5.1 and Sec. 4.7", "[sensor][lsp]") {
  const auto dlr = nbs::presets::dlr_lsp();
  dlr.validate();
  CHECK(dlr.range.min_m == 0.15);
  CHECK(dlr.range.max_m == 0.45);
  CHECK(dlr.noise.sigma_m(0.3) == Approx(nbs::RangeNoise::thesis_lsp().sigma_m(0.3)));
  const auto sc = nbs::presets::scancontrol_2700_100();
  sc.validate();
  CHECK(sc.points_per_profile == 640);
  CHECK(sc.fan_angle_rad == Approx(14.25 * std::numbers::pi / 180.0));
  CHECK(sc.range.min_m == 0.3);
  CHECK(sc.range.max_m == 0.6);
}

TEST_CASE("LSP parameter validation names field and value", "[sensor][lsp][bad-input]") {
  auto bad = [](auto mutate) {
    nbs::LaserStripeProfiler s = nbs::presets::dlr_lsp();
    mutate(s);
    return s;
  };
  CHECK_THROWS_WITH(bad([](auto& s) { s.points_per_profile = 0; }).validate(),
                    Contains("points_per_profile") && Contains("0"));
  CHECK_THROWS_WITH(bad([](auto& s) { s.fan_angle_rad = std::nan(""); }).validate(), Contains("fan_angle_rad"));
  CHECK_THROWS_WITH(bad([](auto& s) { s.fan_angle_rad = 4.0; }).validate(), Contains("fan_angle_rad"));
  CHECK_THROWS_WITH(bad([](auto& s) { s.range.min_m = -0.1; }).validate(), Contains("range.min_m") && Contains("-0.1"));
  CHECK_THROWS_WITH(bad([](auto& s) { s.range.max_m = 0.1; }).validate(), Contains("range.max_m"));
  CHECK_THROWS_WITH(bad([](auto& s) { s.profile_spacing_m = 0.0; }).validate(), Contains("profile_spacing_m"));
  CHECK_THROWS_AS(nbs::presets::dlr_lsp().profile_count(-1.0), nbs::InvalidArgument);
  nbs::Pose skewed = nbs::Pose::Identity();
  skewed.linear()(0, 1) = 0.5;
  CHECK_THROWS_WITH(nbs::presets::dlr_lsp().profile_directions(skewed), Contains("not orthonormal"));
  nbs::Pose nan_pose = nbs::Pose::Identity();
  nan_pose.translation().x() = std::nan("");
  CHECK_THROWS_WITH(nbs::presets::dlr_lsp().profile_directions(nan_pose), Contains("non-finite"));
}
