// SPDX-License-Identifier: BSD-3-Clause
// The issue-18 test objects (sim/test_objects.hpp): closed and outward oriented part by part, their volume, area and
// extent against the analytic values of the polygonal solids, and the OBJ files in data/meshes/test-objects/ equal
// to the generator. NBS_WRITE_TEST_OBJECTS=DIR rewrites the files into DIR (the generator program).

#include "nbs_catch.hpp"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <numbers>
#include <string>
#include <utility>

#include "nbs/io/load_mesh.hpp"
#include "nbs/sim/test_objects.hpp"

using namespace nbs;
using Catch::Matchers::WithinRel;

namespace {

constexpr double kPi = std::numbers::pi;

/// Signed volume by the divergence theorem, m³ (positive for outward triangles).
double signed_volume(const IndexedMesh& m) {
  double v = 0.0;
  for (std::size_t t = 0; t < m.triangles.size(); ++t) v += m.corner(t, 0).dot(m.corner(t, 1).cross(m.corner(t, 2)));
  return v / 6.0;
}

/// Every directed edge exactly once and its reverse exactly once: closed, two triangles per edge, consistently
/// oriented.
bool closed_and_oriented(const IndexedMesh& m) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  for (const auto& [e, n] : directed) {
    const auto rev = directed.find({e.second, e.first});
    if (n != 1 || rev == directed.end() || rev->second != 1) return false;
  }
  return true;
}

// Analytic values of the polygonal parts.
struct Solid {
  double volume = 0.0, area = 0.0;
  Solid& operator+=(const Solid& o) {
    volume += o.volume;
    area += o.area;
    return *this;
  }
};
Solid box(double dx, double dy, double dz) { return {dx * dy * dz, 2 * (dx * dy + dy * dz + dx * dz)}; }
double ngon_area(double r, int n) { return 0.5 * n * r * r * std::sin(2 * kPi / n); }
double ngon_perimeter(double r, int n) { return 2 * n * r * std::sin(kPi / n); }
Solid prism(double r, double h, int n) { return {ngon_area(r, n) * h, 2 * ngon_area(r, n) + ngon_perimeter(r, n) * h}; }
Solid cup(double h, double ro, double ri, double floor, int n) {
  return {ngon_area(ro, n) * h - ngon_area(ri, n) * (h - floor),
          ngon_area(ro, n) + ngon_perimeter(ro, n) * h + (ngon_area(ro, n) - ngon_area(ri, n)) +
              ngon_perimeter(ri, n) * (h - floor) + ngon_area(ri, n)};
}
/// n segments between planes at angle step Δ = 2π/n; each is a union of planar isosceles trapezoids. Volume (Pappus
/// for the wedge, exact for a polygon symmetric about ρ = R): n sin Δ · A_k · R. Area: per trapezoid ½ (c_j +
/// c_{j+1}) · height, chords c = 2ρ sin(Δ/2), height from the ρ step (projected by cos(Δ/2)) and the y step.
Solid torus(double big_r, double r, int n, int k) {
  const double d = 2 * kPi / n;
  Solid s{n * std::sin(d) * ngon_area(r, k) * big_r, 0.0};
  for (int j = 0; j < k; ++j) {
    const double p0 = 2 * kPi * j / k, p1 = 2 * kPi * (j + 1) / k;
    const double rho0 = big_r + r * std::cos(p0), rho1 = big_r + r * std::cos(p1);
    const double dy = r * (std::sin(p1) - std::sin(p0)), drho = (rho1 - rho0) * std::cos(d / 2);
    s.area += n * 0.5 * 2 * std::sin(d / 2) * (rho0 + rho1) * std::sqrt(drho * drho + dy * dy);
  }
  return s;
}

Solid expected(TestObject o) {
  Solid s;
  switch (o) {
    case TestObject::table:
      s += box(0.16, 0.10, 0.03);
      for (int i = 0; i < 4; ++i) s += box(0.012, 0.012, 0.08);
      break;
    case TestObject::car:
      s += box(0.16, 0.07, 0.045);
      s += box(0.075, 0.06, 0.03);
      for (int i = 0; i < 4; ++i) s += prism(0.022, 0.016, 48);
      break;
    case TestObject::mug:
      s += cup(0.1, 0.04, 0.036, 0.006, 64);
      s += torus(0.024, 0.006, 48, 16);
      break;
    case TestObject::mushroom:
      s += prism(0.016, 0.04, 48);
      s += prism(0.07, 0.03, 72);
      break;
    case TestObject::plate: s += box(0.16, 0.006, 0.12); break;
  }
  return s;
}

/// Extent (x, y, z) of the bounding box, m.
Vec3 expected_extent(TestObject o) {
  switch (o) {
    case TestObject::table: return {0.16, 0.10, 0.11};
    case TestObject::car: return {0.16, 0.07 + 2 * 0.016, 0.10};
    case TestObject::mug: return {0.04 + 0.058 + 0.03, 0.08, 0.10};  // x: the handle's outer rim at 0.088
    case TestObject::mushroom: return {0.14, 0.14, 0.065};
    case TestObject::plate: return {0.16, 0.006, 0.12};
  }
  return {};
}

}  // namespace

TEST_CASE("test objects: closed, outward, the analytic volume, area and extent, standing on z = 0", "[sim]") {
  for (const TestObject o : kTestObjects) {
    INFO(test_object_name(o));
    const IndexedMesh m = make_test_object(o);
    REQUIRE_NOTHROW(m.validate());
    CHECK(closed_and_oriented(m));
    const Solid s = expected(o);
    CHECK_THAT(signed_volume(m), WithinRel(s.volume, 1e-9));  // > 0: outward; parts summed (they may overlap)
    CHECK_THAT(m.area(), WithinRel(s.area, 1e-9));
    const Aabb b = m.bounds();
    CHECK(std::abs(b.min.z()) < 1e-12);
    CHECK(std::abs(b.center().y()) < 1e-12);  // symmetric about the x–z plane
    const Vec3 e = b.extent(), want = expected_extent(o);
    CHECK((e - want).cwiseAbs().maxCoeff() < 1e-9);
    CHECK(e.maxCoeff() <= 0.16 + 1e-12);
    CHECK(e.maxCoeff() >= 0.10);
  }
}

TEST_CASE("test objects: the OBJ files in data/meshes/test-objects equal the generator", "[sim][io]") {
  const std::string dir = std::string(NBS_DATA_DIR) + "/meshes/test-objects/";
  if (const char* out = std::getenv("NBS_WRITE_TEST_OBJECTS")) {  // the generator program
    for (const TestObject o : kTestObjects) {
      std::ofstream f(std::string(out) + "/" + std::string(test_object_name(o)) + ".obj", std::ios::binary);
      f << test_object_obj(o);
      REQUIRE(f.good());
    }
  }
  for (const TestObject o : kTestObjects) {
    INFO(test_object_name(o));
    const IndexedMesh want = make_test_object(o);
    const IndexedMesh got = load_mesh(dir + std::string(test_object_name(o)) + ".obj");
    REQUIRE(got.vertices.size() == want.vertices.size());
    CHECK(got.triangles == want.triangles);
    double worst = 0.0;
    for (std::size_t i = 0; i < want.vertices.size(); ++i)
      worst = std::max(worst, (got.vertices[i] - want.vertices[i]).cwiseAbs().maxCoeff());
    CHECK(worst <= 5e-7 + 1e-12);  // 6 decimals in the file
  }
}
