// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The open border of an IndexedMesh: its border edges (used by exactly one triangle) and points along them — the
/// rims of a partial model's holes.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/core/types.hpp"
#include "nbs/mesh/indexed_mesh.hpp"

namespace nbs {

/// The border edges of `mesh`: vertex index pairs {a, b}, a < b, of the edges used by exactly one triangle, sorted.
/// Degenerate edges (a triangle repeating a vertex) are skipped. Empty for a closed mesh. O(F log F).
[[nodiscard]] inline std::vector<std::array<std::uint32_t, 2>> border_edges(const IndexedMesh& mesh) {
  using Edge = std::array<std::uint32_t, 2>;
  std::vector<Edge> all;
  all.reserve(3 * mesh.triangles.size());
  for (const auto& f : mesh.triangles)
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint32_t a = f[k], b = f[(k + 1) % 3];
      if (a != b) all.push_back({std::min(a, b), std::max(a, b)});
    }
  std::sort(all.begin(), all.end());
  std::vector<Edge> border;
  for (std::size_t i = 0; i < all.size();) {
    std::size_t j = i + 1;
    while (j < all.size() && all[j] == all[i]) ++j;
    if (j - i == 1) border.push_back(all[i]);
    i = j;
  }
  return border;
}

/// Points along every border edge of `mesh`, at most `spacing_m` apart on each edge (both ends included), metres,
/// the mesh's frame. Throws InvalidArgument unless spacing_m is positive and finite, or if a border vertex index is
/// out of range or a border vertex is not finite.
[[nodiscard]] inline std::vector<Vec3> border_points(const IndexedMesh& mesh, double spacing_m) {
  detail::require(std::isfinite(spacing_m) && spacing_m > 0.0, "border_points: spacing_m must be positive, got ",
                  spacing_m);
  std::vector<Vec3> out;
  for (const auto& [a, b] : border_edges(mesh)) {
    detail::require(b < mesh.vertices.size(), "border_points: vertex index ", b, " out of range (",
                    mesh.vertices.size(), " vertices)");
    const Vec3 &p = mesh.vertices[a], &q = mesh.vertices[b];
    detail::require(p.allFinite() && q.allFinite(), "border_points: border edge {", a, ", ", b,
                    "} has a vertex that is not finite");
    const auto n = static_cast<int>(std::ceil((q - p).norm() / spacing_m));
    for (int i = 0; i <= std::max(n, 1); ++i) out.push_back(p + (q - p) * (static_cast<double>(i) / std::max(n, 1)));
  }
  return out;
}

}  // namespace nbs
