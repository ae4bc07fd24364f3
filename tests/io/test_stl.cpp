// SPDX-License-Identifier: BSD-3-Clause
// STL (binary and ASCII): write → read round trips of a small closed mesh, welding of the shared corners, and
// malformed files (wrong size, bad numbers, missing vertices, truncation) rejected with the file and the problem.
#include "nbs_catch.hpp"

#include <filesystem>
#include <string>

#include "nbs/io/load_mesh.hpp"
#include "nbs/io/read_stl.hpp"
#include "temp_dir.hpp"

using nbs::Vec3;
using nbs_test::Contains;

namespace {

// A tetrahedron with coordinates exact in float32 (4 vertices, 4 outward triangles).
nbs::IndexedMesh tetrahedron() {
  nbs::IndexedMesh m;
  m.vertices = {Vec3(0, 0, 0), Vec3(0.5, 0, 0), Vec3(0, 0.25, 0), Vec3(0, 0, 0.125)};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return m;
}

}  // namespace

TEST_CASE("STL round trip: binary and ASCII give back the mesh, corners welded", "[io][stl]") {
  const nbs::IndexedMesh m = tetrahedron();
  for (const auto format : {nbs::StlFormat::binary, nbs::StlFormat::ascii}) {
    const bool binary = format == nbs::StlFormat::binary;
    const std::string path = (nbs_test::temp_dir() / (binary ? "tet_bin.stl" : "tet_ascii.stl")).string();
    nbs::write_stl(path, m, format);
    for (const nbs::IndexedMesh& r : {nbs::read_stl(path), nbs::load_mesh(path)}) {
      INFO((binary ? "binary" : "ascii"));
      REQUIRE(r.vertices.size() == 4);  // 12 stored corners welded into 4
      REQUIRE(r.triangles.size() == 4);
      for (std::size_t t = 0; t < 4; ++t)
        for (int k = 0; k < 3; ++k) CHECK(r.corner(t, k) == m.corner(t, k));  // exact: float32-representable
    }
  }
  // ASCII keeps doubles to the last bit.
  nbs::IndexedMesh fine = m;
  fine.vertices[1].x() = 0.1;
  const std::string path = (nbs_test::temp_dir() / "tet_fine.stl").string();
  nbs::write_stl(path, fine, nbs::StlFormat::ascii);
  CHECK(nbs::read_stl(path).corner(1, 1).x() == 0.1);
}

TEST_CASE("malformed STL files throw FileError naming the file and the problem", "[io][stl][bad-input]") {
  const auto fails = [](const std::string& name, const std::string& bytes, const std::string& what) {
    const std::string path = nbs_test::write_temp(name, bytes);
    INFO(name);
    CHECK_THROWS_AS(nbs::read_stl(path), nbs::FileError);
    CHECK_THROWS_WITH(nbs::read_stl(path), Contains(name) && Contains(what));
  };
  const std::string facet = "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\n"
                            "endfacet\n";
  fails("short.stl", "abc", "not an STL file");
  fails("no_end.stl", "solid x\n" + facet, "endsolid");
  fails("bad_number.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 zero 0\n",
        "line 4: 'zero' is not a number");
  fails("nan.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 nan 0\n", "not finite");
  fails("two_corners.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\n",
        "line 6: a facet has 2 vertices");
  fails("junk.stl", "solid x\n" + facet + "hello\nendsolid x\n", "unexpected 'hello'");
  fails("no_loop.stl", "solid x\n" + facet + "facet normal 0 0 1\nendfacet\n" + facet + "endsolid x\n",
        "line 10: a facet without 'outer loop'");
  fails("two_loops.stl",
        "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\n"
        "outer loop\nvertex 0 0 1\nvertex 1 0 1\nvertex 0 1 1\nendloop\nendfacet\nendsolid x\n",
        "line 8: a facet has a second 'outer loop'");
  fails("flat.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 2 0 0\nendloop\n"
                    "endfacet\nendsolid\n",
        "zero area");

  // Binary: truncated by one byte, a count larger than the body, a non-finite coordinate.
  const std::string good = (nbs_test::temp_dir() / "good_bin.stl").string();
  nbs::write_stl(good, tetrahedron());
  std::string bytes = nbs::io_detail::read_file_bytes(good);
  REQUIRE(bytes.size() == 84 + 4 * 50);
  fails("truncated.stl", bytes.substr(0, bytes.size() - 1), "declares 4 triangles");
  std::string more = bytes;
  more[80] = 5;
  fails("count.stl", more, "declares 5 triangles (334 bytes) but has 284 bytes");
  std::string inf = bytes;
  inf[84 + 12 + 3] = '\x7f';  // first corner's x: exponent all ones
  inf[84 + 12 + 2] = '\x80';
  fails("inf.stl", inf, "triangle 0 corner 0 is not finite");
  nbs::IndexedMesh huge = tetrahedron();
  huge.vertices[2].y() = 1e39;
  CHECK_THROWS_WITH(nbs::write_stl((nbs_test::temp_dir() / "huge.stl").string(), huge),
                    Contains("huge.stl") && Contains("vertex 2") && Contains("float32"));
  CHECK_FALSE(std::filesystem::exists(nbs_test::temp_dir() / "huge.stl"));
  CHECK_THROWS_WITH(nbs::read_stl((nbs_test::temp_dir() / "missing.stl").string()),
                    Contains("missing.stl") && Contains("cannot open"));
}
