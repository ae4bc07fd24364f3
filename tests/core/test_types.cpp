// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include <cmath>
#include <limits>

#include "nbs/core.hpp"

using nbs::Pose;
using nbs::Vec3;

TEST_CASE("validate_pose accepts rigid transforms and rejects everything else", "[core]") {
  Pose p = Pose::Identity();
  p.rotate(Eigen::AngleAxisd(0.3, Vec3(1, 2, 3).normalized()));
  p.translation() = Vec3(0.1, -0.2, 0.3);
  REQUIRE_NOTHROW(nbs::validate_pose(p));

  Pose nan = p;
  nan.matrix()(0, 3) = std::numeric_limits<double>::quiet_NaN();
  REQUIRE_THROWS_AS(nbs::validate_pose(nan), nbs::InvalidArgument);

  Pose scaled = p;
  scaled.linear() *= 1.01;
  REQUIRE_THROWS_WITH(nbs::validate_pose(scaled), nbs_test::Contains("not orthonormal"));

  Pose mirrored = Pose::Identity();
  mirrored.linear().col(2) *= -1.0;
  REQUIRE_THROWS_WITH(nbs::validate_pose(mirrored), nbs_test::Contains("determinant"));
}

TEST_CASE("Viewpoint::look_at builds the frame of Eq. 4.12", "[core]") {
  const Vec3 pos(0.3, 0.0, 0.1);
  const auto v = nbs::Viewpoint::look_at(pos, Vec3::Zero());
  // s_z points from the position to the target.
  REQUIRE((v.view_direction() - (-pos).normalized()).norm() < 1e-12);
  // right-handed orthonormal basis
  REQUIRE(std::abs(v.x_axis().cross(v.y_axis()).dot(v.view_direction()) - 1.0) < 1e-12);
  REQUIRE(std::abs(v.x_axis().dot(Vec3::UnitZ())) < 1e-12);  // x perpendicular to up
  REQUIRE((v.position() - pos).norm() == 0.0);

  REQUIRE_THROWS_AS(nbs::Viewpoint::look_at(pos, pos), nbs::InvalidArgument);
  REQUIRE_THROWS_AS(nbs::Viewpoint::look_at(Vec3(0, 0, 1), Vec3::Zero(), Vec3::UnitZ()), nbs::InvalidArgument);
}

TEST_CASE("LinearScanPath keeps one rotation and interpolates the position", "[core]") {
  const auto v = nbs::Viewpoint::look_at(Vec3(0.3, -0.15, 0.1), Vec3(0, -0.15, 0.1));
  const nbs::LinearScanPath path(v, Vec3(0.3, 0.15, 0.1));
  REQUIRE(path.length() == Approx(0.3).epsilon(1e-12));
  const Pose mid = path.pose_at(0.5);
  REQUIRE((mid.translation() - Vec3(0.3, 0.0, 0.1)).norm() < 1e-12);
  REQUIRE(mid.linear().isApprox(v.pose().linear()));
  REQUIRE(path.end().view_direction().isApprox(v.view_direction()));
  REQUIRE_THROWS_AS(nbs::LinearScanPath(v, Vec3(std::nan(""), 0, 0)), nbs::InvalidArgument);
}

TEST_CASE("Scan validate names the first broken invariant", "[core]") {
  nbs::Scan s;
  s.profile_poses.push_back(Pose::Identity());
  s.add_point(Vec3(0, 0, 0.3), 0);
  REQUIRE_NOTHROW(s.validate());
  REQUIRE((s.line_of_sight(0) - Vec3::UnitZ()).norm() < 1e-15);
  s.add_point(Vec3(0, 0, 0.3), 3);
  REQUIRE_THROWS_WITH(s.validate(), nbs_test::Contains("point 1") && nbs_test::Contains("profile 3"));
}
