// SPDX-License-Identifier: BSD-3-Clause
// Colour fusion of the streaming mesh (Sec. 5.3) against analytic cases, and the mean colour error metric.
#include "nbs_catch.hpp"

#include <cmath>
#include <vector>

#include "mesh_test_util.hpp"
#include "nbs/mesh/conversion.hpp"
#include "nbs/mesh/streaming_mesh.hpp"
#include "nbs/sim/surface_color.hpp"

using nbs::Rgb;
using nbs::Vec3;

namespace {
constexpr Rgb kRed{255, 0, 0}, kBlue{0, 0, 255};

/// Ground truth: the plane z = 0, |x|, |y| ≤ h, red for x < 0 and blue for x > 0 (two quads without shared vertices,
/// so the colour is exact up to the seam).
nbs::IndexedMesh two_coloured_plane(double h) {
  nbs::IndexedMesh m;
  for (double x0 : {-h, 0.0}) {
    const auto b = static_cast<std::uint32_t>(m.vertices.size());
    m.vertices.insert(m.vertices.end(), {Vec3(x0, -h, 0), Vec3(x0 + h, -h, 0), Vec3(x0 + h, h, 0), Vec3(x0, h, 0)});
    m.triangles.push_back({b, b + 1, b + 2});
    m.triangles.push_back({b, b + 2, b + 3});
    m.colors.insert(m.colors.end(), 4, x0 < 0 ? kRed : kBlue);
  }
  return m;
}
}  // namespace

TEST_CASE("colour fusion on a two-coloured plane: vertices away from the seam exact, error ~0 there", "[mesh][color]") {
  const double h = 0.03;
  nbs::test::PlanePatch plane(h, h);
  nbs::Scan scan = nbs::test::scan_path(plane, nbs::test::down_at(0, 0.04, 0.15), 0.08, {}, 1);
  for (const Vec3& p : scan.points) scan.colors.push_back(p.x() < 0 ? kRed : kBlue);  // the colour of the hit
  const nbs::MeshDistance truth(two_coloured_plane(h));
  for (bool robust : {false, true}) {
    INFO("noise-robust settings: " << robust);
    nbs::StreamingMeshSettings s;
    if (robust) s = nbs::NoiseRobustStreamingMesh::robust(s);
    nbs::StreamingMesh mesh(s);
    mesh.integrate(scan);
    REQUIRE(mesh.has_colors());
    // A measurement adds to a vertex within ~R_r (density_depth: within R_r of its line of sight, rays ≤ 14° off
    // the normal): vertices farther than 2 R_r from the seam see one colour only.
    const double margin = 2.0 * s.reduction_radius_m;
    std::vector<Vec3> far_points;
    std::vector<Rgb> far_colors;
    std::size_t far = 0, mixed = 0;
    for (nbs::VertexId v = 0; v < mesh.vertex_count(); ++v) {
      REQUIRE(mesh.color_count(v) >= 1);
      const double x = mesh.position(v).x();
      if (std::abs(x) <= margin) {
        mixed += mesh.color(v) != kRed && mesh.color(v) != kBlue ? 1 : 0;
        continue;
      }
      ++far;
      CHECK(mesh.color(v) == (x < 0 ? kRed : kBlue));
      far_points.push_back(mesh.position(v));
      far_colors.push_back(mesh.color(v));
    }
    REQUIRE(far > 100);
    CHECK(mixed > 0);  // the seam's vertices average both colours
    CHECK(nbs::mean_color_error(truth, far_points, far_colors) == Approx(0.0).margin(1e-12));
    // Over the whole model the seam costs little: at most the share of seam vertices times the largest distance.
    const nbs::IndexedMesh model = nbs::to_indexed_mesh(mesh);
    REQUIRE(model.colors.size() == model.vertices.size());
    CHECK(nbs::mean_color_error(truth, model) < 0.1);
  }
}

TEST_CASE("colour fusion rule: the rounded mean of the vertex's point and the points it rejected", "[mesh][color]") {
  nbs::StreamingMesh mesh;
  const double rr = mesh.settings().reduction_radius_m;
  const Vec3 down(0, 0, -1);
  CHECK(mesh.insert(Vec3(0, 0, 0), down, kRed) == nbs::InsertResult::pending);
  CHECK(mesh.insert(Vec3(0.5 * rr, 0, 0), down, kBlue) == nbs::InsertResult::too_close);
  CHECK(mesh.insert(Vec3(0, 0.5 * rr, 0), down, Rgb{0, 30, 0}) == nbs::InsertResult::too_close);
  CHECK(mesh.color_count(0) == 3);
  CHECK(mesh.color(0) == Rgb{85, 10, 85});  // (255 + 0 + 0) / 3, 30 / 3, 255 / 3
  // A point without colour stores a vertex with none; a coloured mesh reports black for it.
  CHECK(mesh.insert(Vec3(3 * rr, 0, 0), down) == nbs::InsertResult::pending);
  CHECK(mesh.color_count(1) == 0);
  CHECK(mesh.color(1) == Rgb{0, 0, 0});
  nbs::StreamingMesh plain;
  plain.insert(Vec3(0, 0, 0), down);
  CHECK_FALSE(plain.has_colors());
  CHECK(plain.memory_bytes() > 0);
}

TEST_CASE("a scan whose colours do not match its points is rejected and changes nothing", "[mesh][color][bad-input]") {
  nbs::test::PlanePatch plane(0.02, 0.02);
  nbs::Scan scan = nbs::test::scan_path(plane, nbs::test::down_at(0, 0.02, 0.15), 0.04, {}, 1);
  REQUIRE(scan.size() > 10);
  scan.colors.assign(scan.size() - 1, kRed);
  CHECK_THROWS_WITH(scan.validate(), nbs_test::Contains("colours"));
  nbs::StreamingMesh mesh;
  CHECK_THROWS_AS(mesh.integrate(scan), nbs::InvalidArgument);
  CHECK(mesh.vertex_count() == 0);
  CHECK_FALSE(mesh.has_colors());
  scan.colors.push_back(kBlue);
  CHECK_NOTHROW(scan.validate());
  nbs::IndexedMesh m = two_coloured_plane(0.01);
  m.colors.pop_back();
  CHECK_THROWS_AS(m.validate(), nbs::InvalidArgument);
}

TEST_CASE("procedural colours: seeded two-colour 3-D checker, interpolated on the surface", "[mesh][color]") {
  nbs::IndexedMesh m = two_coloured_plane(0.05);
  m.colors.clear();
  const auto a = nbs::procedural_colors(m, 7), b = nbs::procedural_colors(m, 7), c = nbs::procedural_colors(m, 8);
  REQUIRE(a.size() == m.vertices.size());
  CHECK(a == b);
  CHECK(a != c);
  for (const Rgb& x : a)
    for (const Rgb& y : a)
      if (x != y)
        for (std::size_t k = 0; k < 3; ++k) CHECK(std::abs(int(x[k]) - int(y[k])) >= 96);
  // surface_color interpolates: at a corner its colour, a quarter along an edge 3/4 of one and 1/4 of the other.
  m.colors = {kRed, kBlue, kBlue, kRed, kRed, kBlue, kBlue, kRed};
  CHECK(nbs::surface_color(m, 0, m.vertices[0]) == kRed);
  CHECK(nbs::surface_color(m, 0, 0.75 * m.vertices[0] + 0.25 * m.vertices[1]) == Rgb{191, 0, 64});
  CHECK(nbs::color_distance(kRed, kBlue) == Approx(std::sqrt(2.0)));
}
