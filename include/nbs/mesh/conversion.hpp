// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Conversion of any EdgeMesh to an owning IndexedMesh (vertices in at least one face, with their normals).

#include <vector>

#include "nbs/mesh/indexed_mesh.hpp"
#include "nbs/mesh/mesh_concept.hpp"

namespace nbs {

/// Copies the faces of `mesh` and the vertices they use (renumbered densely in id order) with their normals.
/// Vertices without a triangle are dropped. Face orientation is kept (counter-clockwise around the normal). A
/// ColoredMesh with colours gives its vertex colours too.
template <EdgeMesh M>
[[nodiscard]] IndexedMesh to_indexed_mesh(const M& mesh) {
  std::vector<std::uint32_t> index(mesh.vertex_count(), kNoVertex);
  mesh.for_each_face([&](const MeshFace& f) { index[f.a] = index[f.b] = index[f.c] = 0; });
  bool colored = false;
  if constexpr (ColoredMesh<M>) colored = mesh.has_colors();
  IndexedMesh out;
  for (std::size_t v = 0; v < index.size(); ++v) {
    if (index[v] == kNoVertex) continue;
    index[v] = static_cast<std::uint32_t>(out.vertices.size());
    out.vertices.push_back(mesh.position(static_cast<VertexId>(v)));
    out.normals.push_back(mesh.normal(static_cast<VertexId>(v)));
    if constexpr (ColoredMesh<M>)
      if (colored) out.colors.push_back(mesh.color(static_cast<VertexId>(v)));
  }
  out.triangles.reserve(mesh.face_count());
  mesh.for_each_face([&](const MeshFace& f) { out.triangles.push_back({index[f.a], index[f.b], index[f.c]}); });
  return out;
}

}  // namespace nbs
