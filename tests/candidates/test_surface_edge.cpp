// SPDX-License-Identifier: BSD-3-Clause
// SEE (Surface Edge Explorer) as a peer generator: the density classification against a brute-force oracle and an
// analytic plane patch, the thinning against its greedy rule, the view geometry, and bad parameters (the generator
// on a scanned strip is in test_generators.cpp, next to the other generators' plane scan).
#include "nbs_catch.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "nbs/candidates/surface_edge_explorer.hpp"
#include "nbs/core/detail/random.hpp"
#include "nbs_random.hpp"

using nbs::DensityClass;
using nbs::Vec3;

namespace {

/// The rule of classify_density written out in O(n²).
std::vector<DensityClass> brute_force_classes(const std::vector<Vec3>& pts, double r, int k) {
  const auto within = [&](std::size_t i, std::size_t j) { return i != j && (pts[i] - pts[j]).squaredNorm() <= r * r; };
  std::vector<bool> core(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    int n = 0;
    for (std::size_t j = 0; j < pts.size(); ++j) n += within(i, j) ? 1 : 0;
    core[i] = n >= k;
  }
  std::vector<DensityClass> out(pts.size(), DensityClass::outlier);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (core[i]) {
      out[i] = DensityClass::core;
      continue;
    }
    bool c = false, o = false;
    for (std::size_t j = 0; j < pts.size(); ++j)
      if (within(i, j)) (core[j] ? c : o) = true;
    if (c && o) out[i] = DensityClass::frontier;
  }
  return out;
}

/// A 21 × 21 grid of 1 mm spacing in z = 0, corner at the origin.
std::vector<Vec3> grid_patch() {
  std::vector<Vec3> pts;
  for (int i = 0; i <= 20; ++i)
    for (int j = 0; j <= 20; ++j) pts.emplace_back(0.001 * i, 0.001 * j, 0.0);
  return pts;
}

}  // namespace

TEST_CASE("SEE density: plane patch interior is core, its border rows frontier, isolated points outliers", "[see]") {
  // r = 2.5 mm on a 1 mm grid: an interior point has 20 neighbours (|i|, |j| ≤ 2, i² + j² ≤ 6), a point one row in
  // from the border 17, a border point 12. With k = 20 the points ≥ 2 rows from every border are core; the two
  // border rows touch core points (2 mm away) and each other: frontier; a corner's r-ball holds no core point
  // ((2, 2) is 2.83 mm away): outlier. Two isolated points far away: outliers.
  std::vector<Vec3> pts = grid_patch();
  pts.emplace_back(0.1, 0.1, 0.0);
  pts.emplace_back(0.1, 0.1005, 0.0);
  const auto cls = nbs::classify_density(pts, 0.0025, 20);
  REQUIRE(cls.size() == pts.size());
  for (int i = 0; i <= 20; ++i)
    for (int j = 0; j <= 20; ++j) {
      INFO("grid point " << i << ", " << j);
      const bool interior = i >= 2 && i <= 18 && j >= 2 && j <= 18, corner = i % 20 == 0 && j % 20 == 0;
      const DensityClass expected = interior ? DensityClass::core : corner ? DensityClass::outlier : DensityClass::frontier;
      CHECK(cls[static_cast<std::size_t>(21 * i + j)] == expected);
    }
  CHECK(cls[pts.size() - 2] == DensityClass::outlier);
  CHECK(cls[pts.size() - 1] == DensityClass::outlier);
  CHECK(cls == brute_force_classes(pts, 0.0025, 20));
}

TEST_CASE("SEE density: kd-tree classification equals the brute-force oracle on jittered, thinned patches", "[see]") {
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    std::vector<Vec3> pts;
    std::uint64_t state = seed;
    const auto uniform = [&] { return double(nbs::detail::splitmix64(state++) >> 11) * 0x1.0p-53; };
    for (const Vec3& p : grid_patch())
      if (uniform() > 0.3 * p.x() / 0.02)  // thinner towards +x: a density gradient
        pts.push_back(p + 0.0003 * (nbs_test::random_vec3(uniform) - Vec3::Constant(0.5)));
    INFO("seed " << seed << ", " << pts.size() << " points");
    for (const int k : {5, 12, 18}) CHECK(nbs::classify_density(pts, 0.0025, k) == brute_force_classes(pts, 0.0025, k));
  }
}

TEST_CASE("SEE thinning: kept points pairwise farther than the spacing, every point near a kept one", "[see]") {
  std::vector<Vec3> pts;
  std::uint64_t state = 9;
  const auto uniform = [&] { return double(nbs::detail::splitmix64(state++) >> 11) * 0x1.0p-53; };
  for (int i = 0; i < 2000; ++i) pts.push_back(nbs_test::random_vec3(uniform).cwiseProduct(Vec3(0.03, 0.03, 0.002)));
  const double s = 0.002;
  const std::vector<std::size_t> kept = nbs::thin_points(pts, s);
  REQUIRE(kept.size() > 50);
  CHECK(kept.front() == 0);
  CHECK(std::is_sorted(kept.begin(), kept.end()));
  for (std::size_t a = 0; a < kept.size(); ++a)
    for (std::size_t b = a + 1; b < kept.size(); ++b) CHECK((pts[kept[a]] - pts[kept[b]]).norm() > s);
  // Oracle: the greedy rule in O(n²): i is kept iff no earlier kept point lies within s.
  std::vector<std::size_t> oracle;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    bool near = false;
    for (const std::size_t k : oracle) near = near || (pts[k] - pts[i]).squaredNorm() <= s * s;
    if (!near) oracle.push_back(i);
  }
  CHECK(kept == oracle);
}

TEST_CASE("SEE view: at d_s along the normal, sweeping across the frontier edge, aim on the frontier point", "[see]") {
  const Vec3 p(0.01, -0.02, 0.03), n = Vec3(0, 1, 1).normalized(), out(1, 0, 0);
  const double d_s = 0.3, length = 0.1;
  const nbs::ScanCandidate c = nbs::surface_edge_view(p, n, out, d_s, length, 7);
  const nbs::Pose& t = c.path.start().pose();
  CHECK((t.linear().col(2) + n).norm() < 1e-12);                  // s_z = −n
  CHECK((t.linear().col(1) - out).norm() < 1e-12);                // s_y = outward
  CHECK((t.linear().col(0) - out.cross(-n)).norm() < 1e-12);      // fan along the edge
  CHECK((t.translation() - (p + d_s * n - 0.05 * out)).norm() < 1e-12);
  CHECK((c.path.end_position() - (p + d_s * n + 0.05 * out)).norm() < 1e-12);
  CHECK(c.aim.point == p);
  CHECK(c.index == 7);
  CHECK(c.source == nbs::CandidateSource::surface_edge);
  const nbs::ScanCandidate area = nbs::surface_edge_view(p, n, out, d_s, 0.0, 0);
  CHECK(area.path.length() == 0.0);
  CHECK((area.path.start().position() - (p + d_s * n)).norm() < 1e-12);
}

TEST_CASE("SEE: bad parameters throw naming the value", "[see]") {
  const auto throws_naming = [](auto&& f, const std::string& what) {
    try {
      f();
      FAIL("no exception for " << what);
    } catch (const nbs::InvalidArgument& e) {
      CHECK_THAT(e.what(), nbs_test::Contains(what));
    }
  };
  nbs::SurfaceEdgeSetting s;
  s.radius_m = -0.002;
  throws_naming([&] { (void)nbs::SurfaceEdgeExplorer(s); }, "SurfaceEdge.radius_m");
  throws_naming([&] { (void)nbs::SurfaceEdgeExplorer(s); }, "-0.002");
  s = {};
  s.min_neighbours = 0;
  throws_naming([&] { (void)nbs::SurfaceEdgeExplorer(s); }, "min_neighbours must be >= 1, got 0");
  s = {};
  s.spacing_m = std::nan("");
  throws_naming([&] { (void)nbs::SurfaceEdgeExplorer(s); }, "SurfaceEdge.spacing_m");
  s = {};
  s.repeat_angle_rad = 4.0;
  throws_naming([&] { (void)nbs::SurfaceEdgeExplorer(s); }, "SurfaceEdge.repeat_angle_rad");
  const std::vector<Vec3> pts = grid_patch();
  throws_naming([&] { (void)nbs::classify_density(pts, 0.0, 5); }, "radius_m");
  throws_naming([&] { (void)nbs::classify_density(pts, 0.002, -3); }, "got -3");
  std::vector<Vec3> bad = pts;
  bad[5].x() = std::nan("");
  throws_naming([&] { (void)nbs::classify_density(bad, 0.002, 3); }, "point 5 is not finite");
}
