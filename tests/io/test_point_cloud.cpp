// SPDX-License-Identifier: BSD-3-Clause
// PLY point clouds: read_ply_points against write_ply_points (round trips in every format, with and without
// normals and colours), a mesh file read as a cloud, and malformed clouds rejected with file, record and value.
#include "nbs_catch.hpp"

#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "nbs/io/load_mesh.hpp"
#include "nbs/io/load_point_cloud.hpp"
#include "nbs/io/read_ply_points.hpp"
#include "nbs/io/write_pcd.hpp"
#include "nbs/io/write_ply.hpp"
#include "random_cloud.hpp"
#include "temp_dir.hpp"

using nbs_test::Contains;
using nbs::Vec3;

namespace {
const std::string kPointsHead = "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n";
}  // namespace

TEST_CASE("read_ply_points reads write_ply_points' output back exactly", "[io][ply][points]") {
  int k = 0;
  for (const nbs::PlyFormat format :
       {nbs::PlyFormat::ascii, nbs::PlyFormat::binary_little_endian, nbs::PlyFormat::binary_big_endian}) {
    for (const bool normals : {false, true}) {
      for (const bool colors : {false, true}) {
        INFO("format " << static_cast<int>(format) << " normals " << normals << " colours " << colors);
        const nbs::PointCloud c = nbs_test::random_cloud(257, normals, colors, static_cast<unsigned>(++k));
        const std::string path = (nbs_test::temp_dir() / ("cloud" + std::to_string(k) + ".ply")).string();
        nbs::write_ply_points(path, c.points, c.normals, c.colors, format);
        const nbs::PointCloud r = nbs::read_ply_points(path);
        CHECK(r.points == c.points);  // doubles are written with 17 digits in ascii: exact
        CHECK(r.normals == c.normals);
        CHECK(r.colors == c.colors);
        CHECK_NOTHROW(r.validate());
      }
    }
  }
}

TEST_CASE("read_ply_points: a mesh file gives its vertices; float and int properties of any order", "[io][ply][points]") {
  const nbs::PointCloud m = nbs::read_ply_points(nbs_test::fixture("binary_le_tetrahedron.ply"));
  CHECK(m.size() == nbs::read_ply(nbs_test::fixture("binary_le_tetrahedron.ply")).vertices.size());
  CHECK(!m.has_normals());
  const nbs::PointCloud c = nbs::read_ply_points_bytes(
      "mem.ply", "ply\nformat ascii 1.0\nelement vertex 2\nproperty uchar blue\nproperty float nz\nproperty float z\n"
                 "property uchar green\nproperty float ny\nproperty float y\nproperty uchar red\nproperty float nx\n"
                 "property float x\nproperty int intensity\nend_header\n"
                 "3 1 0.5 2 0 0.25 1 0 0.125 9\n255 0 -1 0 1 0 0 0 0 9\n");
  REQUIRE(c.size() == 2);
  CHECK(c.points[0] == Vec3(0.125, 0.25, 0.5));
  CHECK(c.normals[0] == Vec3(0, 0, 1));
  CHECK(c.colors[0] == nbs::Rgb{1, 2, 3});
  CHECK(c.colors[1] == nbs::Rgb{0, 0, 255});
}

TEST_CASE("read_ply_points rejects malformed clouds naming file, record and value", "[io][ply][points][bad-input]") {
  struct Bad {
    const char* name;
    std::string text;
    const char* message;
  };
  const std::vector<Bad> cases = {
      {"partial_normals", kPointsHead + "property float nx\nproperty float ny\nend_header\n0 0 0 1 0\n1 1 1 0 1\n",
       "only some of the normal properties"},
      {"partial_colours", kPointsHead + "property uchar red\nend_header\n0 0 0 1\n1 1 1 2\n", "only some of the colour"},
      {"nan_normal", kPointsHead + "property float nx\nproperty float ny\nproperty float nz\nend_header\n0 0 0 1 0 0\n1 1 1 nan 0 0\n",
       "record 1: non-finite normal"},
      {"colour_256", kPointsHead + "property int red\nproperty int green\nproperty int blue\nend_header\n0 0 0 1 2 3\n1 1 1 1 256 3\n",
       "colour green = 256"},
      {"colour_fraction", kPointsHead + "property float red\nproperty float green\nproperty float blue\nend_header\n0 0 0 0.5 0 0\n1 1 1 0 0 0\n",
       "colour red = 0.5"},
      {"nan_point", kPointsHead + "end_header\n0 nan 0\n1 1 1\n", "non-finite coordinate"},
      {"no_points", "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nend_header\n",
       "no points"},
      {"list_normal", kPointsHead + "property list uchar float nx\nproperty float ny\nproperty float nz\nend_header\n",
       "'nx' must be a scalar"},
      {"truncated", kPointsHead + "end_header\n0 0 0\n", "truncated"},
  };
  for (const Bad& b : cases) {
    INFO(b.name);
    const std::string path = nbs_test::write_temp(std::string(b.name) + ".ply", b.text);
    CHECK_THROWS_AS(nbs::read_ply_points(path), nbs::FileError);
    CHECK_THROWS_WITH(nbs::read_ply_points(path), Contains(path) && Contains(b.message));
  }
}

TEST_CASE("load_point_cloud picks the reader by content; load_mesh names a cloud as a cloud", "[io][points]") {
  const nbs::PointCloud c = nbs_test::random_cloud(20, true, false, 3);
  const auto dir = nbs_test::temp_dir();
  const std::string ply = (dir / "lpc.ply").string(), pcd = (dir / "lpc.pcd").string(),
                    odd = (dir / "lpc_pcd_content.dat").string(), txt = (dir / "lpc.txt").string();
  nbs::write_ply_points(ply, c.points, c.normals);
  nbs::write_pcd(pcd, c);
  std::filesystem::copy_file(pcd, odd, std::filesystem::copy_options::overwrite_existing);
  for (const std::string& p : {ply, pcd, odd}) {
    INFO(p);
    const nbs::PointCloud r = nbs::load_point_cloud(p);
    CHECK(r.points == c.points);
    CHECK(r.normals == c.normals);
  }
  { std::ofstream(txt) << "1 2 3\n"; }
  CHECK_THROWS_WITH(nbs::load_point_cloud(txt), Contains(txt) && Contains("unknown point-cloud format"));
  // The report: load_mesh on write_ply_points' output said only "mesh is empty".
  CHECK_THROWS_WITH(nbs::load_mesh(ply),
                    Contains(ply) && Contains("20 vertices and no faces: a point cloud, not a mesh"));
}
