// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include <array>
#include <cmath>
#include <vector>
#include <limits>

#include "mesh_test_util.hpp"
#include "nbs/mesh/conversion.hpp"
#include "nbs/mesh/density.hpp"
#include "nbs/mesh/invariants.hpp"

using nbs::Vec3;
using nbs::test::down_at;

namespace {
const double kCa = nbs::Parameters{}.completeness_radius_m;  // r of c_a (3 mm)

/// The thesis's settings (a bare StreamingMesh) or the noise-robust ones (the planner's default), for the tests that
/// both must pass.
nbs::StreamingMeshSettings settings_for(bool noise_robust) {
  nbs::StreamingMeshSettings s;
  return noise_robust ? nbs::NoiseRobustStreamingMesh::robust(s) : s;
}

void require_consistent(const nbs::StreamingMesh& mesh) {
  const auto rep = nbs::check_invariants(mesh, mesh.settings().reduction_radius_m);
  INFO(rep.problems);
  REQUIRE(rep.ok());
}
}  // namespace

TEST_CASE("plane: consistent, normals match, scanned region covered", "[mesh]") {
  nbs::test::PlanePatch plane(0.03, 0.03);
  const nbs::test::StripeSensor sensor;
  const auto start = down_at(0, 0.04, 0.15);
  nbs::StreamingMesh mesh;
  mesh.integrate(nbs::test::scan_path(plane, start, 0.08, sensor, 1));
  require_consistent(mesh);
  CHECK(mesh.face_count() > 0);
  CHECK(nbs::test::normal_agreement(mesh, plane, 10.0 * M_PI / 180.0, [](const Vec3&) { return false; }) >= 0.99);
  CHECK(nbs::test::coverage(mesh, nbs::test::scanned_region(plane, start, 0.08, sensor, 10, 10), kCa) >= 0.99);
  // Filled area close to the patch area (the border loses at most about one edge length).
  const auto im = nbs::to_indexed_mesh(mesh);
  CHECK(im.area() == Approx(0.06 * 0.06).epsilon(0.05));
}

TEST_CASE("plane under range noise larger than R_r: with density_depth_m and project_vertices, one layer, true area", "[mesh]") {
  // σ = 1 mm is the thesis noise (Eq. 4.39) at 0.3 m, twice R_r. With the R_r ball alone the vertices form a slab of
  // noisy layers whose tangent-plane triangulations overlap (3-4x the patch area in triangles projected on the plane);
  // the density cylinder along the line of sight and the projection onto the PCA plane keep one layer.
  nbs::test::PlanePatch plane(0.03, 0.03);
  nbs::test::StripeSensor sensor;
  sensor.noise_sigma_m = 0.001;
  sensor.rays = 640;
  nbs::StreamingMeshSettings settings = nbs::StreamingMeshSettings::from(nbs::Parameters{});
  settings.density_depth_m = settings.normal_radius_m;
  settings.project_vertices = true;
  nbs::StreamingMesh mesh(settings);
  for (unsigned k = 0; k < 3; ++k) {
    mesh.integrate(nbs::test::scan_path(plane, down_at(0.002 * k, 0.04, 0.3), 0.08, sensor, 21 + k));
    require_consistent(mesh);
  }
  double projected = 0.0, z2 = 0.0;
  mesh.for_each_face([&](const nbs::MeshFace& f) {
    const Vec3 a = mesh.position(f.a), b = mesh.position(f.b), c = mesh.position(f.c);
    projected += 0.5 * std::abs((b - a).cross(c - a).z());
  });
  std::size_t meshed = 0;
  for (nbs::VertexId v = 0; v < mesh.vertex_count(); ++v)
    if (mesh.in_triangle(v)) {
      z2 += mesh.position(v).z() * mesh.position(v).z();
      ++meshed;
    }
  const double rms = std::sqrt(z2 / static_cast<double>(meshed));
  INFO("projected area " << projected << " m^2, vertex RMS " << rms << " m, vertices " << mesh.vertex_count());
  CHECK(projected == Approx(0.06 * 0.06).epsilon(0.05));  // the plane, once
  CHECK(rms < 0.5 * sensor.noise_sigma_m);                 // vertices on their PCA planes, not at the raw noise
  // One layer: no more stored points than the densest packing of points R_r apart in the plane allows (hexagonal,
  // one per √3/2 R_r²); the R_r ball alone keeps ~3x that many here.
  const double rr = mesh.settings().reduction_radius_m;
  CHECK(static_cast<double>(mesh.vertex_count()) < 0.06 * 0.06 / (std::sqrt(3.0) / 2.0 * rr * rr));
}

TEST_CASE("sphere, cube, cylinder: consistent, normals, coverage", "[mesh]") {
  const bool robust = GENERATE(false, true);
  INFO("noise-robust settings: " << robust);
  nbs::test::StripeSensor sensor;
  sensor.fov_rad = 0.6;
  sensor.rays = 400;
  SECTION("sphere") {
    nbs::test::Sphere sphere(Vec3(0, 0, 0), 0.04);
    const auto start = down_at(0, 0.05, 0.2);
    nbs::StreamingMesh mesh(settings_for(robust));
    mesh.integrate(nbs::test::scan_path(sphere, start, 0.1, sensor, 2));
    require_consistent(mesh);
    CHECK(nbs::test::normal_agreement(mesh, sphere, 10.0 * M_PI / 180.0, [](const Vec3&) { return false; }) >= 0.98);
    // Region seen at incidence below 70°: grazing hits are not expected to be meshed.
    auto region = nbs::test::scanned_region(sphere, start, 0.1, sensor, 10, 10);
    std::erase_if(region, [](const Vec3& p) { return p.normalized().z() < std::cos(70.0 * M_PI / 180.0); });
    CHECK(nbs::test::coverage(mesh, region, kCa) >= 0.99);
  }
  SECTION("cube seen from a diagonal") {
    nbs::test::Box box(Vec3(-0.03, -0.03, 0), Vec3(0.03, 0.03, 0.06));
    const Vec3 z = Vec3(-1, 0, -1).normalized();  // looks at the +x face and the top
    // right-handed sensor frame: x = y × z
    const auto vp = nbs::Viewpoint::from_axes(Vec3(0, -1, 0).cross(z), Vec3(0, -1, 0), z, Vec3(0.15, 0.05, 0.2));
    nbs::StreamingMesh mesh(settings_for(robust));
    mesh.integrate(nbs::test::scan_path(box, vp, 0.1, sensor, 3));
    require_consistent(mesh);
    auto near_edge = [](const Vec3& p) {
      int close = 0;
      for (int i = 0; i < 3; ++i)
        close += (std::abs(p[i] - (i == 2 ? 0.06 : 0.03)) < 0.004 || std::abs(p[i] - (i == 2 ? 0.0 : -0.03)) < 0.004);
      return close >= 2;
    };
    CHECK(nbs::test::normal_agreement(mesh, box, 10.0 * M_PI / 180.0, near_edge) >= 0.98);
    CHECK(nbs::test::coverage(mesh, nbs::test::scanned_region(box, vp, 0.1, sensor, 10, 10), kCa) >= 0.99);
  }
  SECTION("cylinder seen from the side") {
    nbs::test::Cylinder cyl(0, 0, 0.03, 0.0, 0.08);
    const Vec3 z(-1, 0, 0);
    const auto vp = nbs::Viewpoint::from_axes(Vec3(0, 0, 1).cross(z), Vec3(0, 0, 1), z, Vec3(0.2, 0, 0.0));  // x = y × z
    nbs::StreamingMesh mesh(settings_for(robust));
    mesh.integrate(nbs::test::scan_path(cyl, vp, 0.08, sensor, 4));
    require_consistent(mesh);
    CHECK(nbs::test::normal_agreement(mesh, cyl, 10.0 * M_PI / 180.0, [](const Vec3&) { return false; }) >= 0.98);
    auto region = nbs::test::scanned_region(cyl, vp, 0.08, sensor, 10, 10);
    std::erase_if(region, [](const Vec3& p) { return p.x() / 0.03 < std::cos(70.0 * M_PI / 180.0); });
    CHECK(nbs::test::coverage(mesh, region, kCa) >= 0.99);
  }
}

TEST_CASE("rescanning adds no vertex closer than R_r and keeps the mesh consistent", "[mesh]") {
  const bool robust = GENERATE(false, true);
  INFO("noise-robust settings: " << robust);
  nbs::test::PlanePatch plane(0.02, 0.02);
  const nbs::test::StripeSensor sensor;
  nbs::StreamingMesh mesh(settings_for(robust));
  mesh.integrate(nbs::test::scan_path(plane, down_at(0, 0.03, 0.15), 0.06, sensor, 1));
  const std::size_t first = mesh.vertex_count();
  mesh.integrate(nbs::test::scan_path(plane, down_at(0.001, 0.0305, 0.14), 0.06, sensor, 2));
  require_consistent(mesh);  // includes: no two vertices closer than R_r
  CHECK(mesh.vertex_count() >= first);
  CHECK(mesh.stats().too_close > 0);
}

TEST_CASE("border edges read off the per-face masks equal the faces' own border", "[mesh]") {
  // Oracle: check_invariants compares for_each_edge's v_l / v_r (border status read off the masks) with the directed
  // edges of the faces, and for_each_border_edge with for_each_edge; the masks do not depend on integrate vs insert.
  nbs::test::Sphere sphere(Vec3(0, 0, 0), 0.03);
  const auto scan = nbs::test::scan_path(sphere, down_at(0, 0.03, 0.15), 0.06, nbs::test::StripeSensor{}, 7);
  nbs::StreamingMesh fused, pointwise;
  fused.integrate(scan);
  pointwise.begin_scan(scan.profile_poses.front());
  for (std::size_t i = 0; i < scan.size(); ++i) (void)pointwise.insert(scan.points[i], scan.line_of_sight(i));
  require_consistent(fused);
  require_consistent(pointwise);
  const auto border_of = [](const nbs::StreamingMesh& m) {
    std::vector<std::array<nbs::VertexId, 4>> out;
    m.for_each_border_edge([&](const nbs::MeshEdge& e) { out.push_back({e.a, e.b, e.left, e.right}); });
    return out;
  };
  const auto border = border_of(fused);
  CHECK(border.size() > 50);
  CHECK(border == border_of(pointwise));
}

TEST_CASE("the result does not depend on how the stream is split into scans", "[mesh]") {
  const bool robust = GENERATE(false, true);
  INFO("noise-robust settings: " << robust);
  nbs::test::Sphere sphere(Vec3(0, 0, 0), 0.03);
  const auto scan = nbs::test::scan_path(sphere, down_at(0, 0.03, 0.15), 0.06, nbs::test::StripeSensor{}, 5);
  nbs::StreamingMesh whole(settings_for(robust)), parts(settings_for(robust));
  whole.integrate(scan);
  for (std::size_t lo : {std::size_t{0}, scan.size() / 3, 2 * scan.size() / 3}) {
    nbs::Scan part;
    part.profile_poses = scan.profile_poses;
    const std::size_t hi = lo == 2 * scan.size() / 3 ? scan.size() : lo + scan.size() / 3;
    for (std::size_t i = lo; i < hi; ++i) part.add_point(scan.points[i], scan.profile_of_point[i]);
    parts.integrate(part);
  }
  REQUIRE(whole.vertex_count() == parts.vertex_count());
  REQUIRE(whole.face_count() == parts.face_count());
  for (nbs::VertexId v = 0; v < whole.vertex_count(); ++v) {
    REQUIRE(whole.position(v) == parts.position(v));
    REQUIRE(whole.normal(v) == parts.normal(v));
  }
  for (std::size_t f = 0; f < whole.face_count(); ++f) {
    const auto a = whole.face(f), b = parts.face(f);
    REQUIRE((a.a == b.a && a.b == b.b && a.c == b.c));
  }
  CHECK(parts.current_scan() == 3);
}

TEST_CASE("rejected, dropped and degenerate points leave the mesh consistent", "[mesh]") {
  nbs::StreamingMesh mesh;
  const Vec3 down(0, 0, -1);
  // (Invalid points throw: test_mesh_validation.cpp.)
  // Too few neighbours: pending, not meshed.
  CHECK(mesh.insert(Vec3(0, 0, 0), down) == nbs::InsertResult::pending);
  // Duplicates are rejected by the density limitation.
  CHECK(mesh.insert(Vec3(0, 0, 0), down) == nbs::InsertResult::too_close);
  CHECK(mesh.insert(Vec3(0.0001, 0, 0), down) == nbs::InsertResult::too_close);
  // A collinear row never gets a robust normal.
  for (int i = 1; i < 30; ++i) CHECK(mesh.insert(Vec3(0.0006 * i, 0, 0), down) == nbs::InsertResult::pending);
  CHECK(mesh.stats().normal_failures > 0);
  CHECK(mesh.stats().meshed == 0);
  CHECK(mesh.face_count() == 0);
  // Line of sight in the tangent plane: no robust orientation.
  nbs::StreamingMesh side;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) (void)side.insert(Vec3(0.001 * i, 0.001 * j, 0), Vec3(1, 0, 0));
  CHECK(side.stats().meshed == 0);
  // Outside the pass-through box.
  nbs::Aabb box;
  box.extend(Vec3(-0.01, -0.01, -0.01));
  box.extend(Vec3(0.01, 0.01, 0.01));
  nbs::StreamingMesh boxed(nbs::Parameters{}, box);
  CHECK(boxed.insert(Vec3(0.02, 0, 0), down) == nbs::InsertResult::outside);
  CHECK(boxed.stats().outside == 1);
  // Repeated points inside a real scan stream, with either settings.
  nbs::test::PlanePatch plane(0.01, 0.01);
  auto scan = nbs::test::scan_path(plane, down_at(0, 0.015, 0.15), 0.03, nbs::test::StripeSensor{}, 6);
  for (std::size_t i = 5; i < scan.size(); i += 89) scan.points[i] = scan.points[i - 1];
  for (const bool robust : {false, true}) {
    INFO("noise-robust settings: " << robust);
    nbs::StreamingMesh noisy(settings_for(robust));
    noisy.integrate(scan);
    CHECK(noisy.stats().too_close > 0);
    CHECK(noisy.face_count() > 0);
    require_consistent(noisy);
  }
  require_consistent(mesh);
}

TEST_CASE("relative density d = N_act / N_max matches a brute-force count (Eqs. 4.24-4.25)", "[mesh]") {
  nbs::test::PlanePatch plane(0.015, 0.015);
  nbs::StreamingMesh mesh;
  mesh.integrate(nbs::test::scan_path(plane, down_at(0, 0.02, 0.15), 0.04, nbs::test::StripeSensor{}, 7));
  const double rn = mesh.settings().normal_radius_m, rr = mesh.settings().reduction_radius_m;
  CHECK(mesh.max_neighbours() == Approx(std::sqrt(2.0) * M_PI * rn * rn / (rr * rr)));
  for (nbs::VertexId v = 0; v < mesh.vertex_count(); v += 37) {
    std::uint32_t n = 0;
    for (nbs::VertexId q = 0; q < mesh.vertex_count(); ++q)
      n += (mesh.stored_position(q) - mesh.stored_position(v)).norm() <= rn ? 1 : 0;  // N_act counts stored points
    REQUIRE(mesh.neighbour_count(v) == n);
    REQUIRE(mesh.relative_density(v) == Approx(std::min(1.0, n / mesh.max_neighbours())));
  }
  const double dm = nbs::mean_relative_density(mesh);
  CHECK(dm > 0.0);
  CHECK(dm <= 1.0);
}
