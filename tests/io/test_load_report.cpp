// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include <random>
#include <set>
#include <utility>

#include "nbs/io/load_report.hpp"
#include "temp_dir.hpp"

using nbs_test::Contains;

namespace {

// Brute-force oracle: every count from pairwise scans over faces and vertices.
nbs::LoadReport oracle(const nbs::IndexedMesh& m) {
  nbs::LoadReport r;
  r.vertices = m.vertices.size();
  r.faces = m.triangles.size();
  std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const auto& f = m.triangles[t];
    if (m.face_normal_scaled(t).norm() == 0.0) ++r.zero_area_faces;
    for (std::size_t s = 0; s < t; ++s) {
      const auto& g = m.triangles[s];
      if (std::multiset<std::uint32_t>(f.begin(), f.end()) == std::multiset<std::uint32_t>(g.begin(), g.end())) {
        ++r.duplicate_faces;
        break;
      }
    }
    for (int k = 0; k < 3; ++k) {
      const auto a = f[std::size_t(k)], b = f[std::size_t((k + 1) % 3)];
      if (a != b) edges.insert({std::min(a, b), std::max(a, b)});
    }
  }
  for (const auto& [a, b] : edges) {
    int uses = 0, same = 0;
    for (const auto& f : m.triangles)
      for (int k = 0; k < 3; ++k) {
        const auto x = f[std::size_t(k)], y = f[std::size_t((k + 1) % 3)];
        if (x == a && y == b) ++uses, ++same;
        if (x == b && y == a) ++uses;
      }
    if (uses == 1) ++r.boundary_edges;
    if (uses > 2) ++r.non_manifold_edges;
    if (uses == 2 && same != 1) ++r.inconsistent_edges;
  }
  for (std::uint32_t v = 0; v < m.vertices.size(); ++v) {
    bool used = false;
    for (const auto& f : m.triangles) used = used || f[0] == v || f[1] == v || f[2] == v;
    if (!used) ++r.unreferenced_vertices;
  }
  return r;
}

void check_equal(const nbs::LoadReport& a, const nbs::LoadReport& b) {
  CHECK(a.vertices == b.vertices);
  CHECK(a.faces == b.faces);
  CHECK(a.zero_area_faces == b.zero_area_faces);
  CHECK(a.duplicate_faces == b.duplicate_faces);
  CHECK(a.non_manifold_edges == b.non_manifold_edges);
  CHECK(a.boundary_edges == b.boundary_edges);
  CHECK(a.unreferenced_vertices == b.unreferenced_vertices);
  CHECK(a.inconsistent_edges == b.inconsistent_edges);
}

nbs::IndexedMesh tetrahedron() {
  nbs::IndexedMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  return m;
}

}  // namespace

TEST_CASE("inspect_mesh: closed tetrahedron is clean", "[io][load_report]") {
  const auto r = nbs::inspect_mesh(tetrahedron());
  CHECK(r.vertices == 4);
  CHECK(r.faces == 4);
  CHECK(r.zero_area_faces == 0);
  CHECK(r.duplicate_faces == 0);
  CHECK(r.non_manifold_edges == 0);
  CHECK(r.boundary_edges == 0);
  CHECK(r.unreferenced_vertices == 0);
  CHECK(r.inconsistent_edges == 0);
}

TEST_CASE("inspect_mesh: hand-built defects", "[io][load_report]") {
  auto m = tetrahedron();
  m.vertices.push_back({5, 5, 5});               // 4: unreferenced
  m.vertices.push_back({2, 0, 0});               // 5: collinear with 0, 1
  m.triangles.push_back({0, 1, 5});              // zero area; edge 0-1 now used 3 times
  m.triangles.push_back({3, 1, 0});              // duplicate of {0,1,3}; edge 0-1 4 times
  m.triangles[2] = {1, 3, 2};                    // flips face 2: edges 1-2, 2-3, 1-3 inconsistent
  const auto r = nbs::inspect_mesh(m);
  check_equal(r, oracle(m));
  CHECK(r.unreferenced_vertices == 1);
  CHECK(r.zero_area_faces == 1);
  CHECK(r.duplicate_faces == 1);
  CHECK(r.non_manifold_edges == 3);  // 0-1 (4 faces), 1-3 and 0-3 (3 faces each)
  CHECK(r.boundary_edges == 2);      // 1-5, 0-5
  CHECK(r.inconsistent_edges == 2);  // 1-2, 2-3 (1-3 is now non-manifold)
}

TEST_CASE("inspect_mesh: random meshes against the brute-force oracle", "[io][load_report]") {
  std::mt19937 rng(17);
  for (int trial = 0; trial < 200; ++trial) {
    nbs::IndexedMesh m;
    const int nv = 3 + int(rng() % 6);
    std::uniform_int_distribution<int> coord(0, 2);  // coarse grid: coincident and collinear points occur
    for (int i = 0; i < nv; ++i) m.vertices.push_back({double(coord(rng)), double(coord(rng)), double(coord(rng))});
    const int nf = int(rng() % 12);
    for (int i = 0; i < nf; ++i)
      m.triangles.push_back({std::uint32_t(rng() % std::uint32_t(nv)), std::uint32_t(rng() % std::uint32_t(nv)),
                             std::uint32_t(rng() % std::uint32_t(nv))});
    INFO("trial " << trial);
    check_equal(nbs::inspect_mesh(m), oracle(m));
  }
}

TEST_CASE("inspect_mesh: index out of range throws InvalidArgument", "[io][load_report]") {
  auto m = tetrahedron();
  m.triangles.push_back({0, 1, 4});
  CHECK_THROWS_WITH(nbs::inspect_mesh(m), Contains("index 4") && Contains("vertex count 4"));
}

TEST_CASE("load_mesh_with_report: require_manifold", "[io][load_report]") {
  // Three triangles sharing edge 0-1: one non-manifold edge.
  const std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n";
  const std::string path = nbs_test::write_temp("fin.obj", obj);
  nbs::LoadReport r;
  const auto mesh = nbs::load_mesh_with_report(path, r);
  CHECK(mesh.triangles.size() == 3);
  CHECK(r.faces == 3);
  CHECK(r.non_manifold_edges == 1);
  CHECK(r.boundary_edges == 6);

  nbs::LoadReport untouched;
  untouched.faces = 99;
  CHECK_THROWS_AS(nbs::load_mesh_with_report(path, untouched, {true}), nbs::FileError);
  CHECK_THROWS_WITH(nbs::load_mesh_with_report(path, untouched, {true}),
                    Contains(path) && Contains("1 non-manifold edges") && Contains("0 zero-area faces"));
  CHECK(untouched.faces == 99);

  nbs::LoadReport ok;
  CHECK_NOTHROW((void)nbs::load_mesh_with_report(nbs_test::fixture("binary_le_tetrahedron.ply"), ok, {true}));
  CHECK(ok.faces == 4);
  CHECK(ok.non_manifold_edges == 0);
}

TEST_CASE("load_mesh_with_report: every mesh in data/meshes loads", "[io][load_report]") {
  nbs::LoadReport r;
  const auto mesh = nbs::load_mesh_with_report(std::string(NBS_DATA_DIR) + "/meshes/stanford-bunny.obj", r);
  CHECK(r.faces == mesh.triangles.size());
  CHECK(r.vertices == mesh.vertices.size());
  WARN("stanford-bunny.obj: V=" << r.vertices << " F=" << r.faces << " zero-area=" << r.zero_area_faces
                                << " duplicate=" << r.duplicate_faces << " non-manifold=" << r.non_manifold_edges
                                << " boundary=" << r.boundary_edges << " unreferenced=" << r.unreferenced_vertices
                                << " inconsistent=" << r.inconsistent_edges);
}
