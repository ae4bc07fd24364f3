// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include "nbs/io/load_mesh.hpp"
#include "nbs/mesh/normalize.hpp"

using nbs::Vec3;

namespace {
const std::string kBunny = std::string(NBS_DATA_DIR) + "/meshes/stanford-bunny.obj";
}

TEST_CASE("the bundled bunny OBJ loads with its published counts", "[io][obj]") {
  const nbs::IndexedMesh m = nbs::load_mesh(kBunny);
  CHECK(m.vertices.size() == 35947);
  CHECK(m.triangles.size() == 69451);
  REQUIRE_NOTHROW(m.validate());
}

TEST_CASE("normalize_on_pedestal: bunny (y-up) stands upright, 0.16 m, centred, bottom on z = 0", "[mesh][normalize]") {
  const nbs::IndexedMesh raw = nbs::load_mesh(kBunny);
  nbs::IndexedMesh m = raw;
  nbs::normalize_on_pedestal(m, 0.16, nbs::UpAxis::y);
  const nbs::Aabb b = m.bounds();
  CHECK(b.extent().maxCoeff() == Approx(0.16));
  CHECK(b.min.z() == Approx(0.0).margin(1e-12));
  CHECK(b.center().x() == Approx(0.0).margin(1e-12));
  CHECK(b.center().y() == Approx(0.0).margin(1e-12));
  // Upright: the file's y extent (height) became the z extent, scaled uniformly.
  const nbs::Aabb rb = raw.bounds();
  const double scale = 0.16 / rb.extent().maxCoeff();
  CHECK(b.extent().z() == Approx(rb.extent().y() * scale));
  CHECK(b.extent().y() == Approx(rb.extent().z() * scale));
  // The file's top (max y) vertex is now the top (max z) one.
  std::size_t top = 0;
  for (std::size_t i = 0; i < raw.vertices.size(); ++i)
    if (raw.vertices[i].y() > raw.vertices[top].y()) top = i;
  CHECK(m.vertices[top].z() == Approx(b.max.z()));
}

TEST_CASE("normalize_on_pedestal: up-axis rotations are proper and bad input leaves the mesh unchanged",
          "[mesh][normalize][bad-input]") {
  for (auto up : {nbs::UpAxis::x, nbs::UpAxis::y, nbs::UpAxis::z}) {
    const nbs::Mat3 r = nbs::up_axis_to_z(up);
    CHECK(r.determinant() == Approx(1.0));
    CHECK((r.transpose() * r).isApprox(nbs::Mat3::Identity()));
  }
  CHECK(nbs::up_axis_to_z(nbs::UpAxis::x) * Vec3::UnitX() == Vec3::UnitZ());
  CHECK(nbs::up_axis_to_z(nbs::UpAxis::y) * Vec3::UnitY() == Vec3::UnitZ());

  nbs::IndexedMesh tri;
  tri.vertices = {{1, 2, 3}, {2, 2, 3}, {1, 4, 3}};
  tri.triangles = {{0, 1, 2}};
  const nbs::IndexedMesh before = tri;
  CHECK_THROWS_AS(nbs::normalize_on_pedestal(tri, 0.0), nbs::InvalidArgument);
  CHECK_THROWS_AS(nbs::normalize_on_pedestal(tri, std::nan("")), nbs::InvalidArgument);
  CHECK(tri.vertices == before.vertices);
  nbs::IndexedMesh empty;
  CHECK_THROWS_AS(nbs::normalize_on_pedestal(empty), nbs::InvalidArgument);
  nbs::normalize_on_pedestal(tri, 0.5);  // z-up default: extent (1, 2, 0) → largest 2 → scale 0.25
  CHECK(tri.vertices[0].isApprox(Vec3(-0.125, -0.25, 0.0)));
  CHECK(tri.vertices[2].isApprox(Vec3(-0.125, 0.25, 0.0)));
}
