// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include <cmath>
#include <limits>
#include <random>

#include "nbs/sim/mesh_distance.hpp"
#include "test_meshes.hpp"
#include "nbs_random.hpp"

using namespace nbs;

TEST_CASE("closest_point_on_triangle: every Voronoi region of a right triangle", "[sim][distance]") {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  CHECK(closest_point_on_triangle({-1, -1, 2}, a, b, c).isApprox(a));
  CHECK(closest_point_on_triangle({2, -0.5, 1}, a, b, c).isApprox(b));
  CHECK(closest_point_on_triangle({-0.1, 3, 0}, a, b, c).isApprox(c));
  CHECK(closest_point_on_triangle({0.5, -1, 0}, a, b, c).isApprox(Vec3(0.5, 0, 0)));
  CHECK(closest_point_on_triangle({-2, 0.25, 5}, a, b, c).isApprox(Vec3(0, 0.25, 0)));
  CHECK(closest_point_on_triangle({1, 1, -1}, a, b, c).isApprox(Vec3(0.5, 0.5, 0)));
  CHECK(closest_point_on_triangle({0.2, 0.3, 0.7}, a, b, c).isApprox(Vec3(0.2, 0.3, 0)));
  CHECK(point_triangle_distance({0.2, 0.3, 0.7}, a, b, c) == Approx(0.7));
  // Degenerate triangles: a segment and a point.
  CHECK(point_triangle_distance({0.5, 1, 0}, a, b, Vec3(0.5, 0, 0)) == Approx(1.0));
  CHECK(point_triangle_distance({0, 3, 4}, a, a, a) == Approx(5.0));
}

TEST_CASE("closest_point_on_triangle is never beaten by points of the triangle", "[sim][distance]") {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(-1, 1), w(0, 1);
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3 a = nbs_test::random_vec3(u, rng), b = nbs_test::random_vec3(u, rng), c = nbs_test::random_vec3(u, rng);
    const Vec3 p = 2.0 * nbs_test::random_vec3(u, rng);
    const Vec3 q = closest_point_on_triangle(p, a, b, c);
    const double d = (q - p).norm();
    for (int k = 0; k < 200; ++k) {
      double s = w(rng), t = w(rng);
      if (s + t > 1) s = 1 - s, t = 1 - t;
      const Vec3 x = a + s * (b - a) + t * (c - a);
      REQUIRE((x - p).norm() >= d - 1e-12);
    }
    // q lies on the triangle: its distance to the triangle's plane is zero and it is inside.
    const Vec3 n = (b - a).cross(c - a).normalized();
    REQUIRE(std::abs((q - a).dot(n)) < 1e-9);
  }
}

TEST_CASE("MeshDistance equals brute force over all triangles", "[sim][distance]") {
  // A lumpy sphere plus one large and one degenerate triangle, so bounding radii differ widely.
  IndexedMesh m = test::uv_sphere({0, 0, 0.2}, 0.1, 12, 24);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> jitter(-0.01, 0.01), u(-0.3, 0.5);
  for (auto& v : m.vertices) v += nbs_test::random_vec3(jitter, rng);
  const auto base = static_cast<std::uint32_t>(m.vertices.size());
  m.vertices.insert(m.vertices.end(), {{-0.5, -0.5, 0}, {0.6, -0.5, 0}, {0, 0.6, 0}, {0.3, 0.3, 0.3}, {0.4, 0.4, 0.4}});
  m.triangles.push_back({base, base + 1, base + 2});
  m.triangles.push_back({base + 3, base + 4, base + 3});
  const MeshDistance md(m);
  std::vector<Vec3> queries(400);
  for (auto& q : queries) q = nbs_test::random_vec3(u, rng);
  const std::vector<double> fast = md.distances(queries, 2);
  for (std::size_t i = 0; i < queries.size(); ++i) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
      best = std::min(best, point_triangle_distance(queries[i], m.corner(t, 0), m.corner(t, 1), m.corner(t, 2)));
    REQUIRE(fast[i] == best);
  }
}

TEST_CASE("a model displaced by 1 mm has RMS error 1 mm", "[sim][distance]") {
  const Vec3 c(0, 0, 0.3);
  const IndexedMesh sphere = test::uv_sphere(c, 0.05, 24, 48);
  const MeshDistance md(sphere);
  // Each vertex moved 1 mm outward along its radius; the nearest surface point of the convex mesh is the vertex.
  std::vector<Vec3> model;
  for (const Vec3& v : sphere.vertices) model.push_back(v + 0.001 * (v - c).normalized());
  CHECK(md.rms_error(model) == Approx(0.001).epsilon(1e-9));
  CHECK(md.rms_error(model, 1) == md.rms_error(model, 4));
  // Exact vertices: zero error.
  CHECK(md.rms_error(sphere.vertices) < 1e-15);
}

TEST_CASE("MeshDistance rejects bad input", "[sim][distance][errors]") {
  CHECK_THROWS_AS(MeshDistance(IndexedMesh{}), InvalidArgument);
  const MeshDistance md(test::box_mesh({0, 0, 0}, {1, 1, 1}));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_AS(md.distance(Vec3(nan, 0, 0)), InvalidArgument);
  CHECK_THROWS_AS(md.rms_error(std::vector<Vec3>{}), InvalidArgument);
  CHECK_THROWS_AS(md.rms_error(std::vector<Vec3>{{0, 0, std::numeric_limits<double>::infinity()}}), InvalidArgument);
}
