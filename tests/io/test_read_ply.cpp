// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include "nbs/io/load_mesh.hpp"
#include "temp_dir.hpp"

using nbs::IndexedMesh;
using nbs::Vec3;
using Tri = IndexedMesh::Triangle;

TEST_CASE("ascii PLY: polygon fan triangulation, extra properties and elements skipped", "[io][ply]") {
  const IndexedMesh m = nbs::load_mesh(nbs_test::fixture("ascii_quad_and_triangle.ply"));
  REQUIRE(m.vertices.size() == 5);
  CHECK(m.vertices[4] == Vec3(0.5, 0.5, 1.0));
  const std::vector<Tri> expected{{0, 1, 2}, {0, 2, 3}, {0, 1, 4}};
  CHECK(m.triangles == expected);
  CHECK(m.area() == Approx(1.0 + 0.5 * std::sqrt(1.25)));  // unit square + triangle of base 1, height √1.25
}

TEST_CASE("binary PLY little and big endian give the same tetrahedron", "[io][ply]") {
  const std::vector<Vec3> v{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const std::vector<Tri> f{{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  for (const char* name : {"binary_le_tetrahedron.ply", "binary_be_tetrahedron.ply"}) {
    INFO(name);
    const IndexedMesh m = nbs::load_mesh(nbs_test::fixture(name));
    CHECK(m.vertices == v);
    CHECK(m.triangles == f);
  }
}

TEST_CASE("tristrips: -1 restarts, winding alternates, stitching triangles dropped", "[io][ply]") {
  const IndexedMesh m = nbs::load_mesh(nbs_test::fixture("ascii_tristrips.ply"));
  const std::vector<Tri> expected{{0, 1, 2}, {2, 1, 3}, {1, 4, 3}, {3, 4, 5}};
  CHECK(m.triangles == expected);
  // Consistent winding: every triangle of this planar strip faces +z.
  for (std::size_t t = 0; t < m.triangles.size(); ++t) CHECK(m.face_normal_scaled(t).z() > 0.0);
}

TEST_CASE("PLY with CRLF line endings and sized type names", "[io][ply]") {
  const std::string text =
      "ply\r\nformat ascii 1.0\r\nelement vertex 3\r\nproperty float32 x\r\nproperty float32 y\r\n"
      "property float32 z\r\nelement face 1\r\nproperty list uint8 int32 vertex_index\r\nend_header\r\n"
      "0 0 0\r\n1 0 0\r\n0 1 0\r\n3 0 1 2\r\n";
  const IndexedMesh m = nbs::load_mesh(nbs_test::write_temp("crlf.ply", text));
  CHECK(m.triangles == std::vector<Tri>{{0, 1, 2}});
}
