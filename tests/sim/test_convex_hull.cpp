// SPDX-License-Identifier: BSD-3-Clause
// The 3-D convex hull (nbs/mesh/convex_hull.hpp) against oracles: a cube with interior, face and edge points (6
// square facets, 8 vertices); random points on a sphere (every point inside or on every facet plane, V − E + F = 2,
// every edge used once in each direction); degenerate input throws.

#include "nbs_catch.hpp"

#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <string>

#include "nbs/mesh/convex_hull.hpp"
#include "nbs_random.hpp"

using namespace nbs;

namespace {

/// Checks every point inside or on every facet plane (within ε), V − E + F = 2, each directed edge once and its
/// reverse once, polygons convex and ccw from outside, unit normals.
void check_hull(const ConvexHull& h, const std::vector<Vec3>& points) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
  for (const HullFacet& f : h.facets) {
    CHECK(f.normal.norm() == Approx(1.0));
    REQUIRE(f.polygon.size() >= 3);
    CHECK(f.area > 0.0);
    for (std::size_t i = 0; i < f.polygon.size(); ++i) {
      const Vec3& a = h.vertices[f.polygon[i]];
      const Vec3& b = h.vertices[f.polygon[(i + 1) % f.polygon.size()]];
      const Vec3& c = h.vertices[f.polygon[(i + 2) % f.polygon.size()]];
      CHECK(std::abs(f.normal.dot(a) - f.offset) <= 10 * h.epsilon);
      CHECK((b - a).cross(c - b).dot(f.normal) > 0.0);  // strictly convex, ccw from outside
      ++edges[{f.polygon[i], f.polygon[(i + 1) % f.polygon.size()]}];
    }
    double worst = -std::numeric_limits<double>::infinity();
    for (const Vec3& p : points) worst = std::max(worst, f.normal.dot(p) - f.offset);
    CHECK(worst <= 10 * h.epsilon);
  }
  for (const auto& [e, n] : edges) {
    CHECK(n == 1);
    CHECK(edges.count({e.second, e.first}) == 1);
  }
  const auto v = static_cast<long>(h.vertices.size()), e = static_cast<long>(edges.size() / 2),
             f = static_cast<long>(h.facets.size());
  CHECK(v - e + f == 2);
}

}  // namespace

TEST_CASE("convex hull of a cube with interior, face and edge points: 6 facets, 8 vertices", "[sim][convex_hull]") {
  std::vector<Vec3> pts;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-0.99, 0.99);
  for (int i = 0; i < 200; ++i) pts.push_back(nbs_test::random_vec3(u, rng));  // interior
  for (int i = 0; i < 50; ++i) {                                                // on the ±z faces
    const double x = u(rng), y = u(rng);
    pts.emplace_back(x, y, (i % 2) ? 1.0 : -1.0);
  }
  for (int i = 0; i < 20; ++i) pts.emplace_back(1.0, u(rng), 1.0);                    // on an edge
  for (int c = 0; c < 8; ++c) pts.emplace_back(c & 1 ? 1.0 : -1.0, c & 2 ? 1.0 : -1.0, c & 4 ? 1.0 : -1.0);
  pts.push_back(pts.back());  // a duplicate corner
  const ConvexHull h = convex_hull(pts);
  CHECK(h.vertices.size() == 8);
  REQUIRE(h.facets.size() == 6);
  for (const HullFacet& f : h.facets) {
    CHECK(f.polygon.size() == 4);
    CHECK(f.area == Approx(4.0));
    CHECK(f.offset == Approx(1.0));
    CHECK(f.normal.cwiseAbs().maxCoeff() == Approx(1.0));
  }
  for (const Vec3& v : h.vertices) CHECK(v.cwiseAbs().minCoeff() == 1.0);
  check_hull(h, pts);
  // Deterministic: the same input gives the same hull.
  const ConvexHull h2 = convex_hull(pts);
  CHECK(h2.input_index == h.input_index);
}

TEST_CASE("convex hull of random points on a sphere contains every point, V - E + F = 2", "[sim][convex_hull]") {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> g;
  std::vector<Vec3> pts;
  for (int i = 0; i < 2000; ++i) pts.push_back(0.05 * nbs_test::random_vec3(g, rng).normalized() + Vec3(1, 2, 0));
  for (int i = 0; i < 500; ++i) pts.push_back(0.03 * nbs_test::random_vec3(g, rng).normalized() + Vec3(1, 2, 0));
  const ConvexHull h = convex_hull(pts);
  CHECK(h.vertices.size() == 2000);  // every sphere point is a vertex, no inner one
  check_hull(h, pts);
  double area = 0.0;
  for (const HullFacet& f : h.facets) area += f.area;
  CHECK(area < 4 * std::numbers::pi * 0.05 * 0.05);
  CHECK(area > 0.98 * 4 * std::numbers::pi * 0.05 * 0.05);
}

TEST_CASE("convex hull: degenerate input throws naming the problem", "[sim][convex_hull]") {
  const auto message = [](const std::vector<Vec3>& pts) {
    try {
      (void)convex_hull(pts);
    } catch (const InvalidArgument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK(message({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}).find("at least 4") != std::string::npos);
  CHECK(message({{0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}}).find("coincide") != std::string::npos);
  CHECK(message({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}}).find("collinear") != std::string::npos);
  CHECK(message({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 1e-12}}).find("coplanar") != std::string::npos);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK(message({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, nan}}).find("point 3 is not finite") != std::string::npos);
  CHECK(message({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}) == "no error");
}

TEST_CASE("convex hull: a surface that is not closed is refused (the output check)", "[sim][convex_hull]") {
  std::vector<Vec3> corners;
  for (int i = 0; i < 8; ++i) corners.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  const ConvexHull good = convex_hull(corners);  // six quads
  REQUIRE(good.facets[0].polygon.size() == 4);
  CHECK_NOTHROW(detail::require_closed_hull(good, 1e-9));
  ConvexHull dropped = good;  // a corner dropped from one facet only: its two edges have no reverse
  dropped.facets[0].polygon.pop_back();
  CHECK_THROWS_WITH(detail::require_closed_hull(dropped, 1e-9), nbs_test::Contains("not a closed convex polytope"));
  ConvexHull sliver = good;
  sliver.facets[0].polygon.resize(2);
  CHECK_THROWS_WITH(detail::require_closed_hull(sliver, 1e-9), nbs_test::Contains("has 2 vertices"));
}
