// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// IndexedMesh: an owning indexed triangle set (vertices + triangles), used for ground-truth objects and export.

#include <array>
#include <cstdint>
#include <vector>

#include "nbs/core/types.hpp"

namespace nbs {

/// Owning indexed triangle mesh. Coordinates in metres (world frame once normalised).
/// Invariants (checked by `validate()`): every vertex finite, every index < vertices.size(), normals and colours
/// empty or one per vertex.
/// Degenerate (zero-area) triangles are allowed in the container; algorithms that cannot use them skip them.
struct IndexedMesh {
  using Triangle = std::array<std::uint32_t, 3>;

  std::vector<Vec3> vertices;      ///< \#V vertex positions.
  std::vector<Triangle> triangles; ///< \#F triangles, counter-clockwise seen from outside where known.
  std::vector<Vec3> normals;       ///< optional per-vertex unit normals: empty, or one per vertex.
  std::vector<Rgb> colors;         ///< optional per-vertex colours: empty, or one per vertex.

  [[nodiscard]] bool empty() const { return triangles.empty(); }

  /// Corner `k` (0..2) of triangle `t`.
  [[nodiscard]] const Vec3& corner(std::size_t t, int k) const { return vertices[triangles[t][k]]; }

  /// Non-normalised face normal (b−a)×(c−a); its norm is twice the triangle area.
  [[nodiscard]] Vec3 face_normal_scaled(std::size_t t) const {
    const Vec3& a = corner(t, 0);
    return (corner(t, 1) - a).cross(corner(t, 2) - a);
  }
  [[nodiscard]] double triangle_area(std::size_t t) const { return 0.5 * face_normal_scaled(t).norm(); }

  /// Total surface area, square metres.
  [[nodiscard]] double area() const {
    double a = 0.0;
    for (std::size_t t = 0; t < triangles.size(); ++t) a += triangle_area(t);
    return a;
  }

  /// Axis-aligned bounds of the vertices referenced by triangles (empty box if there are none).
  [[nodiscard]] Aabb bounds() const {
    Aabb box;
    for (const auto& tri : triangles)
      for (auto i : tri) box.extend(vertices[i]);
    return box;
  }

  /// Throws InvalidArgument (naming the first offending vertex/triangle) if an invariant is violated or the mesh
  /// has no triangle of positive area.
  void validate() const {
    detail::require(!triangles.empty(), "mesh is empty: it has ", vertices.size(), " vertices and no triangles");
    for (std::size_t i = 0; i < vertices.size(); ++i)
      detail::require(vertices[i].allFinite(), "mesh vertex ", i, " is not finite: (", vertices[i].transpose(), ")");
    detail::require(normals.empty() || normals.size() == vertices.size(), "mesh has ", normals.size(),
                    " normals for ", vertices.size(), " vertices");
    detail::require(colors.empty() || colors.size() == vertices.size(), "mesh has ", colors.size(),
                    " colours for ", vertices.size(), " vertices");
    bool any_area = false;
    for (std::size_t t = 0; t < triangles.size(); ++t) {
      for (auto i : triangles[t])
        detail::require(i < vertices.size(), "mesh triangle ", t, " refers to vertex ", i, " but the mesh has ",
                        vertices.size(), " vertices");
      any_area = any_area || triangle_area(t) > 0.0;
    }
    detail::require(any_area, "mesh has ", triangles.size(), " triangles but all of them have zero area");
  }
};

}  // namespace nbs
