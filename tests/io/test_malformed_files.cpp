// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include <cstdint>
#include <random>

#include "nbs/io/load_mesh.hpp"
#include "temp_dir.hpp"

using nbs_test::Contains;

namespace {

const std::string kHead =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
const std::string kBody = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";

struct Case {
  const char* name;
  std::string text;
  const char* message;
};

/// Each case, written to "<name><ext>", makes `read` throw FileError naming the file and containing the message.
template <class Read>
void check_rejected(const std::vector<Case>& cases, const std::string& ext, Read read) {
  for (const auto& c : cases) {
    INFO(c.name);
    const std::string path = nbs_test::write_temp(std::string(c.name) + ext, c.text);
    CHECK_THROWS_AS(read(path), nbs::FileError);
    CHECK_THROWS_WITH(read(path), Contains(path) && Contains(c.message));
  }
}

}  // namespace

TEST_CASE("malformed PLY files throw FileError naming file, place and problem", "[io][ply][bad-input]") {
  REQUIRE_NOTHROW(nbs::read_ply(nbs_test::write_temp("good.ply", kHead + kBody)));
  const std::vector<Case> cases{
      {"not_ply", "hello\nworld\n", "first line must be 'ply'"},
      {"no_end_header", "ply\nformat ascii 1.0\nelement vertex 3\n", "end_header"},
      {"no_format", "ply\nelement vertex 0\nend_header\n", "no 'format'"},
      {"bad_format", "ply\nformat ebcdic 1.0\nend_header\n", "unknown format 'ebcdic'"},
      {"bad_version", "ply\nformat ascii 2.0\nend_header\n", "format <encoding> 1.0"},
      {"bad_keyword", "ply\nformat ascii 1.0\nfoo bar\nend_header\n", "line 3: unknown header keyword 'foo'"},
      {"bad_count", "ply\nformat ascii 1.0\nelement vertex -3\nend_header\n", "invalid count '-3'"},
      {"bad_type", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n",
       "unknown property type 'float128'"},
      {"property_first", "ply\nformat ascii 1.0\nproperty float x\nend_header\n", "before any 'element'"},
      {"float_count", "ply\nformat ascii 1.0\nelement face 1\nproperty list float int vertex_indices\nend_header\n",
       "count type must be an integer"},
      {"list_x",
       "ply\nformat ascii 1.0\nelement vertex 1\nproperty list uchar float x\nproperty float y\nproperty float z\n"
       "end_header\n1 0 0 0\n",
       "scalar property 'x'"},
      {"missing_z", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n0 0\n",
       "scalar property 'z'"},
      {"float_indices",
       "ply\nformat ascii 1.0\nelement face 0\nproperty list uchar float vertex_indices\nend_header\n",
       "integer item type"},
      {"no_index_list", "ply\nformat ascii 1.0\nelement face 0\nproperty int flags\nend_header\n",
       "no 'vertex_indices'"},
      {"truncated_ascii", kHead + "0 0 0\n1 0 0\n", "element 'vertex' declares 3 records"},
      {"truncated_line", kHead + "0 0 0\n1 0 0\n0 1\n3 0 1 2\n", "line 12, element 'vertex' record 2: line ends"},
      {"index_range", kHead + "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "vertex index 3 out of range [0, 3)"},
      {"negative_index", kHead + "0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n", "vertex index -1 out of range"},
      {"two_vertex_face", kHead + "0 0 0\n1 0 0\n0 1 0\n2 0 1\n", "at least 3 vertices"},
      {"extra_values", kHead + "0 0 0 7\n1 0 0\n0 1 0\n3 0 1 2\n", "unexpected extra value"},
      {"not_a_number", kHead + "0 zero 0\n1 0 0\n0 1 0\n3 0 1 2\n", "'zero' is not a number"},
      {"nan", kHead + "0 nan 0\n1 0 0\n0 1 0\n3 0 1 2\n", "non-finite coordinate"},
      {"not_integer", kHead + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2.5\n", "'2.5' is not an integer"},
      {"count_overflow", kHead + "0 0 0\n1 0 0\n0 1 0\n300 0 1 2\n", "300 is out of range for its type"},
      {"trailing_garbage", kHead + kBody + "junk\n", "unexpected byte(s) after the last element"},
      {"huge_count", "ply\nformat ascii 1.0\nelement vertex 99999999999\nproperty float x\nend_header\n0\n",
       "99999999999 vertices exceed the 32-bit index range"},
      {"huge_face_count",
       "ply\nformat binary_little_endian 1.0\nelement face 4000000000\nproperty list uchar int vertex_indices\n"
       "end_header\n\x03",
       "element 'face' declares 4000000000 records but only 1 bytes follow"},
      {"no_faces", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
                   "end_header\n0 0 0\n",
       "1 vertices and no faces: a point cloud, not a mesh"},
      {"zero_area", kHead + "0 0 0\n0 0 0\n0 0 0\n3 0 1 2\n", "zero area"},
      {"truncated_binary",
       "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
       "property float z\nend_header\n" + std::string(20, '\0'),
       "declares 2 records"},
      // 78 bytes that hung the reader: 2^64 - 1 records of zero bytes each.
      {"no_properties",
       "ply\nformat binary_little_endian 1.0\nelement nothing 18446744073709551615\nend_header\n",
       "element 'nothing' has 18446744073709551615 records but no properties"},
      {"truncated_list",
       "ply\nformat binary_big_endian 1.0\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
       "\x03" + std::string(8, '\0'),
       "truncated"},
  };
  check_rejected(cases, ".ply", [](const std::string& p) { return nbs::read_ply(p); });
}

TEST_CASE("every truncation and seeded byte corruption of a binary PLY fails cleanly or loads a valid mesh",
          "[io][ply][bad-input]") {
  std::ifstream in(nbs_test::fixture("binary_le_tetrahedron.ply"), std::ios::binary);
  const std::string good((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  REQUIRE(good.size() > 100);
  for (std::size_t n = 0; n < good.size(); ++n) {
    const std::string path = nbs_test::write_temp("cut.ply", good.substr(0, n));
    INFO("truncated to " << n << " bytes");
    CHECK_THROWS_AS(nbs::read_ply(path), nbs::FileError);
  }
  std::mt19937_64 rng(7);
  int loaded = 0, rejected = 0;
  for (int trial = 0; trial < 300; ++trial) {
    std::string bad = good;
    for (int k = 0; k < 3; ++k) bad[rng() % bad.size()] = static_cast<char>(rng() & 0xFF);
    const std::string path = nbs_test::write_temp("flip.ply", bad);
    try {
      const nbs::IndexedMesh m = nbs::read_ply(path);
      m.validate();  // whatever loads must satisfy the invariants
      ++loaded;
    } catch (const nbs::FileError&) {
      ++rejected;
    }
  }
  CHECK(loaded + rejected == 300);
  CHECK(rejected > 0);
}

TEST_CASE("load_mesh rejects missing files, unknown formats and broken OBJ files", "[io][bad-input]") {
  CHECK_THROWS_WITH(nbs::load_mesh((nbs_test::temp_dir() / "missing.ply").string()), Contains("cannot open"));
  CHECK_THROWS_WITH(nbs::load_mesh(nbs_test::write_temp("mesh.xyz", "solid x\n")), Contains("unknown mesh format"));
  CHECK_THROWS_WITH(nbs::load_mesh(nbs_test::write_temp("empty.obj", "")), Contains("empty.obj"));
  CHECK_THROWS_WITH(nbs::load_mesh(nbs_test::write_temp("bad_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")),
                    Contains("bad_index.obj"));
  CHECK_THROWS_AS(nbs::load_mesh(nbs_test::write_temp("binary.obj", std::string("\x01\x02\x7f\x00garbage", 11))),
                  nbs::FileError);
  CHECK_THROWS_WITH(nbs::load_mesh(nbs_test::write_temp("no_faces.obj", "v 0 0 0\nv 1 0 0\n")),
                    Contains("no_faces.obj") && Contains("mesh is empty"));
}

TEST_CASE("OBJ coordinates and face indices are parsed strictly", "[io][obj][bad-input]") {
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  const std::vector<Case> cases{
      {"obj_nan", "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "line 1: vertex coordinate 'nan' is not finite"},
      {"obj_inf", tri + "v 0 0 -inf\nf 1 2 4\n", "line 4: vertex coordinate '-inf' is not finite"},
      {"obj_garbage", "v abc 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "line 1: 'abc' is not a number"},
      {"obj_short_v", "v 0 0\n", "line 1: a vertex needs 3 coordinates, got 2"},
      {"obj_overflow", tri + "v 1 1 0\nf 1 2 4294967299\n", "line 5: vertex index 4294967299 is out of range"},
      {"obj_beyond", tri + "f 1 2 4\n", "line 4: vertex index 4 but the file has 3 vertices"},
      {"obj_relative", tri + "f -1 -2 -4\n", "relative vertex index -4 but only 3 vertices precede it"},
      {"obj_zero", tri + "f 0 1 2\n", "'0' is not a vertex reference"},
      {"obj_bad_ref", tri + "f 1 2 x/1\n", "'x/1' is not a vertex reference"},
      {"obj_two", tri + "f 1 2\n", "a face needs at least 3 vertices, got 2"},
  };
  check_rejected(cases, ".obj", [](const std::string& p) { return nbs::load_mesh(p); });
  // The accepted forms still load: relative indices, v/vt/vn references, comments, a quad (two triangles).
  const auto m = nbs::load_mesh(nbs_test::write_temp(
      "forms.obj", "# c\n" + tri + "v 1 1 0 # corner\nvt 0 0\nvn 0 0 1\nf -4 -3 -1\nf 1/1/1 4//1 3\nf 1 2 4 3\n"));
  REQUIRE(m.vertices.size() == 4);
  REQUIRE(m.triangles.size() == 4);
  CHECK(m.triangles[0] == nbs::IndexedMesh::Triangle{0, 1, 3});
  CHECK(m.triangles[1] == nbs::IndexedMesh::Triangle{0, 3, 2});
}

TEST_CASE("read_ply_bytes / read_obj_bytes equal the file readers, errors included", "[io][bad-input]") {
  auto slurp = [](const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  auto same = [](const nbs::IndexedMesh& a, const nbs::IndexedMesh& b) {
    return a.vertices == b.vertices && a.triangles == b.triangles;
  };
  for (const char* name : {"binary_le_tetrahedron.ply", "binary_be_tetrahedron.ply", "ascii_tristrips.ply",
                           "ascii_quad_and_triangle.ply"}) {
    INFO(name);
    const std::string path = nbs_test::fixture(name);
    CHECK(same(nbs::read_ply_bytes(path, slurp(path)), nbs::read_ply(path)));
  }
  const std::string obj = nbs_test::write_temp("quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
  CHECK(same(nbs::read_obj_bytes(obj, slurp(obj)), nbs::read_obj(obj)));
  CHECK(nbs::read_obj_bytes("mem.obj", slurp(obj)).triangles.size() == 2);
  CHECK_THROWS_WITH(nbs::read_ply_bytes("mem.ply", kHead + "0 0 0\n1 0 0\n"), Contains("mem.ply"));
  CHECK_THROWS_WITH(nbs::read_obj_bytes("mem.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"), Contains("mem.obj"));
}
