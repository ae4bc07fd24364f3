// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include <fstream>
#include <random>
#include <sstream>

#include "nbs/io/load_mesh.hpp"
#include "nbs/io/write_ply.hpp"
#include "nbs/mesh/ply.hpp"
#include "temp_dir.hpp"
#include "nbs_random.hpp"

TEST_CASE("write_ply then load_mesh round-trips a mesh exactly in every encoding", "[io][ply]") {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  nbs::IndexedMesh m;
  for (int i = 0; i < 50; ++i) m.vertices.push_back(nbs_test::random_vec3(u, rng));
  for (std::uint32_t i = 0; i + 2 < 50; ++i) m.triangles.push_back({i, i + 1, i + 2});
  for (auto format : {nbs::PlyFormat::ascii, nbs::PlyFormat::binary_little_endian, nbs::PlyFormat::binary_big_endian}) {
    const std::string path = (nbs_test::temp_dir() / "roundtrip.ply").string();
    nbs::write_ply(path, m, format);
    const nbs::IndexedMesh back = nbs::load_mesh(path);
    CHECK(back.vertices == m.vertices);
    CHECK(back.triangles == m.triangles);
  }
  nbs::IndexedMesh bad = m;
  bad.triangles.push_back({0, 1, 50});
  CHECK_THROWS_AS(nbs::write_ply((nbs_test::temp_dir() / "bad.ply").string(), bad), nbs::InvalidArgument);
}

TEST_CASE("write_ply_points writes points, normals and colours", "[io][ply]") {
  const std::vector<nbs::Vec3> p{{0.125, -2, 3}, {4, 5, 6.5}};
  const std::vector<nbs::Vec3> n{{0, 0, 1}, {1, 0, 0}};
  const std::vector<nbs::Rgb> c{{255, 0, 7}, {1, 2, 3}};
  const std::string path = (nbs_test::temp_dir() / "cloud.ply").string();
  nbs::write_ply_points(path, p, n, c, nbs::PlyFormat::ascii);
  std::ifstream in(path);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto body = text.substr(text.find("end_header\n") + 11);
  CHECK(text.find("element vertex 2\n") != std::string::npos);
  CHECK(text.find("property uchar red\n") != std::string::npos);
  CHECK(body == "0.125 -2 3 0 0 1 255 0 7\n4 5 6.5 1 0 0 1 2 3\n");
  // Binary: header then 2 × (6 doubles + 3 bytes).
  nbs::write_ply_points(path, p, n, c);
  std::ifstream bin(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(bin)), std::istreambuf_iterator<char>());
  CHECK(bytes.size() - (bytes.find("end_header\n") + 11) == 2 * (6 * 8 + 3));
  CHECK_THROWS_AS(nbs::write_ply_points(path, p, std::vector<nbs::Vec3>(1)), nbs::InvalidArgument);
  CHECK_THROWS_WITH(nbs::write_ply_points("/nonexistent-dir/x.ply", p), nbs_test::Contains("cannot open"));
}

TEST_CASE("vertex colours round-trip through write_mesh_ply / write_ply and load_mesh; partial colours rejected",
          "[io][ply][color]") {
  nbs::IndexedMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0.5}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.colors = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {7, 128, 254}};
  const std::string path = (nbs_test::temp_dir() / "colored.ply").string();
  for (bool ascii : {true, false}) {
    nbs::write_mesh_ply(path, m, ascii);
    const nbs::IndexedMesh back = nbs::load_mesh(path);
    CHECK(back.vertices == m.vertices);
    CHECK(back.colors == m.colors);
  }
  nbs::write_ply(path, m, nbs::PlyFormat::binary_big_endian);
  CHECK(nbs::load_mesh(path).colors == m.colors);
  nbs::IndexedMesh plain = m;
  plain.colors.clear();
  nbs::write_mesh_ply(path, plain);
  CHECK(nbs::load_mesh(path).colors.empty());
  const std::string partial = (nbs_test::temp_dir() / "partial.ply").string();
  {
    std::ofstream out(partial);
    out << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
           "property uchar red\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
           "0 0 0 1\n1 0 0 2\n0 1 0 3\n3 0 1 2\n";
  }
  CHECK_THROWS_WITH(nbs::load_mesh(partial), nbs_test::Contains("only some of the colour properties"));
}
