// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include "nbs/candidates/sphere_search.hpp"

using nbs::Vec3;

TEST_CASE("sphere search yields 81 paths of 0.3 m looking at the centre (Sec. 4.7.2)", "[candidates]") {
  const Vec3 c(0.0, 0.0, 0.08);
  const auto paths = nbs::sphere_scan_paths(c, 0.3);
  REQUIRE(paths.size() == 81);
  for (const auto& p : paths) {
    CHECK(p.length() == Approx(0.30).epsilon(1e-12));
    const nbs::Pose mid = p.pose_at(0.5);
    const Vec3 to_c = (c - mid.translation());
    CHECK(to_c.norm() == Approx(0.3).epsilon(1e-12));
    CHECK(mid.linear().col(2).dot(to_c.normalized()) == Approx(1.0).epsilon(1e-12));  // s_z looks at the centre
    CHECK(std::abs(mid.linear().col(0).z()) < 1e-9);                                 // stripe (s_x) horizontal
    CHECK(mid.translation().z() >= c.z() - 1e-12);                                   // never below the centre
    // motion along s_y (Sec. 4.3.2 convention)
    CHECK((p.end_position() - p.start().position()).normalized().dot(p.start().y_axis()) == Approx(1.0));
  }
  nbs::SphereSearchSetting s;
  s.inclinations = 0;
  CHECK_THROWS_AS(nbs::sphere_scan_paths(c, 0.3, s), nbs::InvalidArgument);
  CHECK_THROWS_AS(nbs::sphere_scan_paths(c, -0.3), nbs::InvalidArgument);
}
