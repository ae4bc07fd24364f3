// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include <cmath>
#include <limits>

#include "nbs/sim/surface_samples.hpp"
#include "test_meshes.hpp"

using namespace nbs;

namespace {

// Two disjoint triangles in the plane z = 1 with areas 3/2 and 1/2 (ratio 3:1).
IndexedMesh two_triangles() {
  IndexedMesh m;
  m.vertices = {{0, 0, 1}, {3, 0, 1}, {0, 1, 1}, {10, 0, 1}, {11, 0, 1}, {10, 1, 1}};
  m.triangles = {{0, 1, 2}, {3, 4, 5}};
  return m;
}

// Barycentric coordinates of p in triangle (a, b, c) (p in its plane).
Vec3 barycentric(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  const double area2 = n.squaredNorm();
  const double u = (c - b).cross(p - b).dot(n) / area2;
  const double v = (a - c).cross(p - c).dot(n) / area2;
  return {u, v, 1.0 - u - v};
}

}  // namespace

TEST_CASE("sample_surface is area-uniform across triangles (3:1 within binomial tolerance)", "[sim][samples]") {
  const IndexedMesh m = two_triangles();
  const std::size_t n = 40000;
  const SurfaceSamples s = sample_surface(m, n, 7);
  REQUIRE(s.size() == n);
  std::size_t in_big = 0;
  for (auto t : s.triangle) in_big += (t == 0) ? 1 : 0;
  const double p = 0.75, sd = std::sqrt(n * p * (1 - p));
  CHECK(std::abs(double(in_big) - n * p) < 5.0 * sd);
}

TEST_CASE("sample_surface is uniform inside a triangle and lies on it", "[sim][samples]") {
  const IndexedMesh m = two_triangles();
  const SurfaceSamples s = sample_surface(m, 20000, 3);
  std::size_t central = 0, big = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const auto t = s.triangle[i];
    const Vec3 w = barycentric(s.points[i], m.corner(t, 0), m.corner(t, 1), m.corner(t, 2));
    REQUIRE(w.minCoeff() >= -1e-12);
    REQUIRE(std::abs(s.points[i].z() - 1.0) < 1e-12);
    REQUIRE(std::abs(std::abs(s.normals[i].z()) - 1.0) < 1e-12);
    if (t == 0) {
      ++big;
      central += (w.maxCoeff() <= 0.5) ? 1 : 0;  // medial triangle: a quarter of the area
    }
  }
  const double sd = std::sqrt(big * 0.25 * 0.75);
  CHECK(std::abs(double(central) - 0.25 * big) < 5.0 * sd);
}

TEST_CASE("sample_surface is reproducible per seed and skips zero-area triangles", "[sim][samples]") {
  IndexedMesh m = two_triangles();
  m.vertices.push_back({5, 5, 1});
  m.triangles.push_back({6, 6, 6});  // zero area, between the others in the cumulative table
  std::swap(m.triangles[1], m.triangles[2]);
  const SurfaceSamples a = sample_surface(m, 2000, 11);
  const SurfaceSamples b = sample_surface(m, 2000, 11);
  const SurfaceSamples c = sample_surface(m, 2000, 12);
  CHECK(a.points == b.points);
  CHECK(a.triangle == b.triangle);
  CHECK(a.points != c.points);
  for (auto t : a.triangle) REQUIRE(t != 1);
}

TEST_CASE("sample_surface_density gives ceil(area * density) samples", "[sim][samples]") {
  const IndexedMesh m = two_triangles();  // area 2
  CHECK(sample_surface_density(m, 100.25, 1).size() == 201);
}

TEST_CASE("bottom samples: near-horizontal faces within the band above the pedestal", "[sim][samples]") {
  const IndexedMesh cube = test::box_mesh({0, 0, 0}, {0.1, 0.1, 0.1});
  const SurfaceSamples s = sample_surface(cube, 6000, 5);
  std::size_t bottom = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const bool expected = s.points[i].z() < 1e-12 && std::abs(s.normals[i].z()) > 0.5;
    REQUIRE(s.bottom[i] == expected);
    bottom += expected ? 1 : 0;
  }
  CHECK(s.non_bottom_count() == s.size() - bottom);
  const double sd = std::sqrt(6000.0 * (1.0 / 6) * (5.0 / 6));
  CHECK(std::abs(double(bottom) - 1000.0) < 5 * sd);
  // A floating object has no bottom.
  const IndexedMesh lifted = test::box_mesh({0, 0, 0.01}, {0.1, 0.1, 0.11});
  CHECK(sample_surface(lifted, 1000, 5).non_bottom_count() == 1000);
}

TEST_CASE("sample_surface rejects bad input", "[sim][samples][errors]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_AS(sample_surface(IndexedMesh{}, 10, 1), InvalidArgument);
  IndexedMesh m = two_triangles();
  CHECK_THROWS_AS(sample_surface(m, 0, 1), InvalidArgument);
  CHECK_THROWS_AS(sample_surface_density(m, 0.0, 1), InvalidArgument);
  CHECK_THROWS_AS(sample_surface_density(m, nan, 1), InvalidArgument);
  CHECK_THROWS_AS(sample_surface(m, 10, 1, BottomRule{0.0, -1.0}), InvalidArgument);
  CHECK_THROWS_AS(sample_surface(m, 10, 1, BottomRule{nan}), InvalidArgument);
  m.vertices[0].x() = nan;
  CHECK_THROWS_AS(sample_surface(m, 10, 1), InvalidArgument);
}
