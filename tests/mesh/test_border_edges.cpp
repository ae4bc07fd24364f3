// SPDX-License-Identifier: BSD-3-Clause
// border_edges / border_points (mesh/border_edges.hpp) against a brute-force count of each edge's triangles.
#include "nbs_catch.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "nbs/mesh/border_edges.hpp"

namespace {

using nbs::IndexedMesh;
using nbs::Vec3;

/// A (n+1)×(n+1) vertex grid on z = 0 with spacing 0.01 m, two triangles per cell, cells with keep(i, j) false left
/// out (a hole).
template <class Keep>
IndexedMesh border_test_grid(int n, Keep keep) {
  IndexedMesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.vertices.emplace_back(0.01 * i, 0.01 * j, 0.0);
  const auto id = [n](int i, int j) { return static_cast<std::uint32_t>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      if (keep(i, j)) {
        m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
        m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      }
  return m;
}

/// Brute force: every edge of every triangle whose {min, max} pair appears in exactly one triangle.
std::vector<std::array<std::uint32_t, 2>> border_edges_brute(const IndexedMesh& m) {
  std::vector<std::array<std::uint32_t, 2>> out;
  for (const auto& f : m.triangles)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = std::min(f[k], f[(k + 1) % 3]), b = std::max(f[k], f[(k + 1) % 3]);
      if (a == b) continue;
      int uses = 0;
      for (const auto& g : m.triangles)
        for (int l = 0; l < 3; ++l)
          uses += std::min(g[l], g[(l + 1) % 3]) == a && std::max(g[l], g[(l + 1) % 3]) == b;
      if (uses == 1) out.push_back({a, b});
    }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

TEST_CASE("border_edges: a grid with a hole, a closed tetrahedron, a lone triangle", "[mesh][border]") {
  const IndexedMesh holed = border_test_grid(6, [](int i, int j) { return !(i >= 2 && i < 4 && j >= 2 && j < 5); });
  const auto border = nbs::border_edges(holed);
  CHECK(border == border_edges_brute(holed));
  CHECK(border.size() == 4 * 6 + 2 * (2 + 3));  // the outer square and the hole's 2×3 cell rim
  const IndexedMesh full = border_test_grid(6, [](int, int) { return true; });
  CHECK(nbs::border_edges(full).size() == 4 * 6);

  IndexedMesh tet;
  tet.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  tet.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  CHECK(nbs::border_edges(tet).empty());
  CHECK(nbs::border_points(tet, 0.1).empty());

  IndexedMesh one;
  one.vertices = {Vec3(0, 0, 0), Vec3(0.1, 0, 0), Vec3(0, 0.05, 0)};
  one.triangles = {{2, 1, 0}};
  CHECK(nbs::border_edges(one) == std::vector<std::array<std::uint32_t, 2>>{{0, 1}, {0, 2}, {1, 2}});
  one.triangles.push_back({0, 0, 1});  // repeats a vertex: its edge {0, 0} is skipped, {0, 1} is used twice more
  const auto e = nbs::border_edges(one);
  CHECK(e == std::vector<std::array<std::uint32_t, 2>>{{0, 2}, {1, 2}});
  CHECK(e == border_edges_brute(one));
}

TEST_CASE("border_points: every border edge sampled at most spacing apart, ends included", "[mesh][border]") {
  const IndexedMesh holed = border_test_grid(4, [](int i, int j) { return !(i == 1 && j == 1); });
  const double spacing = 0.003;
  const std::vector<Vec3> pts = nbs::border_points(holed, spacing);
  const auto border = nbs::border_edges(holed);
  CHECK(pts.size() == border.size() * (4 + 1));  // 0.01 m edges: ceil(0.01 / 0.003) = 4 pieces, 5 points
  for (const auto& [a, b] : border) {  // each edge's midpoint lies within spacing / 2 of a point
    const Vec3 mid = 0.5 * (holed.vertices[a] + holed.vertices[b]);
    double best = std::numeric_limits<double>::infinity();
    for (const Vec3& p : pts) best = std::min(best, (p - mid).norm());
    CHECK(best <= 0.5 * spacing + 1e-12);
  }
  for (const Vec3& p : pts) CHECK(p.z() == 0.0);
}

TEST_CASE("border_points bad input", "[mesh][border][bad]") {
  const IndexedMesh m = border_test_grid(2, [](int, int) { return true; });
  CHECK_THROWS_WITH(nbs::border_points(m, 0.0), nbs_test::Contains("spacing_m must be positive, got 0"));
  CHECK_THROWS_WITH(nbs::border_points(m, std::nan("")), nbs_test::Contains("spacing_m must be positive"));
  IndexedMesh bad = m;
  bad.vertices[0].x() = std::numeric_limits<double>::infinity();
  CHECK_THROWS_WITH(nbs::border_points(bad, 0.01), nbs_test::Contains("not finite"));
  IndexedMesh out_of_range = m;
  out_of_range.triangles.push_back({0, 1, 99});
  CHECK_THROWS_WITH(nbs::border_points(out_of_range, 0.01), nbs_test::Contains("vertex index 99 out of range"));
}
