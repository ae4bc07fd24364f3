// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include <cmath>
#include <limits>
#include <set>

#include "nbs/sim/initial_scan_paths.hpp"
#include "nbs/sim/scan_path_length.hpp"

using namespace nbs;

namespace {

double distance_to_box(const Vec3& p, const Aabb& box) {
  return (p - p.cwiseMax(box.min).cwiseMin(box.max)).norm();
}

}  // namespace

TEST_CASE("the 13 initial scan paths look at the box from the standoff and sweep it", "[sim][initial]") {
  Aabb box;
  box.extend({-0.05, -0.03, 0.0});
  box.extend({0.05, 0.03, 0.12});
  const double standoff = 0.3;
  const auto paths = initial_scan_paths(box, standoff);
  REQUIRE(paths.size() == 13);
  std::set<std::tuple<double, double, double>> directions;
  for (std::size_t i = 0; i < paths.size(); ++i) {
    INFO("path " << i);
    const LinearScanPath& p = paths[i];
    const Vec3 mid = 0.5 * (p.start().position() + p.end_position());
    const Vec3 z = p.start().view_direction();
    const Vec3 y = p.start().y_axis();
    // Looks at the box centre from the middle of the path, at the standoff.
    const Vec3 to_c = box.center() - mid;
    CHECK(to_c.dot(z) > 0.0);
    CHECK(to_c.cross(z).norm() < 1e-12);
    CHECK(distance_to_box(mid, box) == Approx(standoff).epsilon(1e-12));
    // Moves along its y axis, horizontally; the fan (x–z plane) starts and ends at the box's extent along y.
    CHECK((p.end_position() - p.start().position()).normalized().isApprox(y, 1e-12));
    CHECK(std::abs(y.z()) < 1e-12);
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (int k = 0; k < 8; ++k) {
      const Vec3 corner((k & 1) ? box.max.x() : box.min.x(), (k & 2) ? box.max.y() : box.min.y(),
                        (k & 4) ? box.max.z() : box.min.z());
      lo = std::min(lo, corner.dot(y));
      hi = std::max(hi, corner.dot(y));
    }
    CHECK(p.start().position().dot(y) == Approx(lo).margin(1e-12));
    CHECK(p.end_position().dot(y) == Approx(hi).margin(1e-12));
    // Above the pedestal and never looking from below.
    CHECK(p.start().position().z() > 0.0);
    CHECK(p.end_position().z() > 0.0);
    CHECK(z.z() <= 1e-12);
    directions.insert({std::round(z.x() * 1e6), std::round(z.y() * 1e6), std::round(z.z() * 1e6)});
  }
  CHECK(directions.size() == 13);  // 13 distinct views
  CHECK(scan_path_length(paths) > 0.0);
  CHECK(travel_length(std::span<const LinearScanPath>(paths).first(1)) == 0.0);
}

TEST_CASE("initial_scan_path index order and the seeded random choice", "[sim][initial]") {
  Aabb box;
  box.extend({0, 0, 0});
  box.extend({0.16, 0.16, 0.16});
  CHECK(initial_scan_path(box, 0.3, 0).start().view_direction().isApprox(Vec3(0, 0, -1)));
  CHECK(initial_scan_path(box, 0.3, 1).start().view_direction().isApprox(Vec3(-1, 0, 0)));
  CHECK(initial_scan_path(box, 0.3, 5).start().view_direction().isApprox(Vec3(-1, 0, -1).normalized()));
  CHECK(initial_scan_path(box, 0.3, 9).start().view_direction().isApprox(Vec3(-1, -1, 0).normalized()));
  std::set<int> seen;
  for (std::uint64_t seed = 0; seed < 500; ++seed) {
    const int i = random_initial_scan_index(seed);
    REQUIRE(i >= 0);
    REQUIRE(i < 13);
    REQUIRE(random_initial_scan_index(seed) == i);
    seen.insert(i);
  }
  CHECK(seen.size() == 13);
}

TEST_CASE("initial_scan_path rejects bad input", "[sim][initial][errors]") {
  Aabb box;
  box.extend({0, 0, 0});
  box.extend({0.1, 0.1, 0.1});
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_AS(initial_scan_path(Aabb{}, 0.3, 0), InvalidArgument);
  CHECK_THROWS_AS(initial_scan_path(box, 0.0, 0), InvalidArgument);
  CHECK_THROWS_AS(initial_scan_path(box, nan, 0), InvalidArgument);
  CHECK_THROWS_AS(initial_scan_path(box, 0.3, 13), InvalidArgument);
  CHECK_THROWS_AS(initial_scan_path(box, 0.3, -1), InvalidArgument);
  Aabb flat;
  flat.extend({0, 0, 0});
  flat.extend({0.1, 0.1, 0});
  CHECK_THROWS_AS(initial_scan_paths(flat, 0.3), InvalidArgument);
  Aabb bad = box;
  bad.max.x() = nan;
  CHECK_THROWS_AS(initial_scan_paths(bad, 0.3), InvalidArgument);
}
