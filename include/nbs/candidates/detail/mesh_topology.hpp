// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Vertex adjacency (CSR) and the triangulated vertices of an EdgeMesh, built once per generator call.

#include <cstdint>
#include <utility>
#include <vector>

#include "nbs/mesh/mesh_concept.hpp"

namespace nbs::detail {

/// Neighbours of vertex v: neighbours[offset[v] .. offset[v+1]). `triangulated[v]` is 1 if v belongs to a face.
struct MeshTopology {
  std::vector<std::uint32_t> offset;
  std::vector<VertexId> neighbours;
  std::vector<char> triangulated;
};

/// Built from the edges of `for_each_edge`, in its order. A mesh that knows its face borders (KnowsFaceBorders) is
/// read face by face instead, without the per-edge twin lookup of for_each_edge: the edge (t[k], t[k+1]) of face
/// t is taken if t[k] < t[k+1], or if it has no twin (then its only face holds it) — each undirected edge once, and for
/// StreamingMesh in the order of its for_each_edge, so the same adjacency lists.
template <EdgeMesh M>
[[nodiscard]] MeshTopology mesh_topology(const M& mesh) {
  const std::size_t n = mesh.vertex_count();
  MeshTopology t;
  t.offset.assign(n + 1, 0);
  t.triangulated.assign(n, 0);
  // One pass over the edges, kept in order for the fill below.
  std::vector<std::pair<VertexId, VertexId>> edges;
  const auto add_edge = [&](VertexId a, VertexId b) {
    if (a >= n || b >= n) return;
    ++t.offset[a + 1];
    ++t.offset[b + 1];
    edges.emplace_back(a, b);
  };
  const auto add_face = [&](const MeshFace& f) {
    for (VertexId v : {f.a, f.b, f.c})
      if (v < n) t.triangulated[v] = 1;
  };
  if constexpr (KnowsFaceBorders<M>) {
    edges.reserve(2 * mesh.face_count());
    for (std::size_t i = 0; i < mesh.face_count(); ++i) {
      const MeshFace f = mesh.face(i);
      const unsigned border = mesh.border_mask(i);
      const VertexId v[3] = {f.a, f.b, f.c};
      for (int k = 0; k < 3; ++k) {
        const VertexId a = v[k], b = v[(k + 1) % 3];
        if (a < b)
          add_edge(a, b);
        else if ((border >> k) & 1u)
          add_edge(b, a);
      }
      add_face(f);
    }
  } else {
    mesh.for_each_edge([&](const MeshEdge& e) { add_edge(e.a, e.b); });
    mesh.for_each_face(add_face);
  }
  for (std::size_t v = 0; v < n; ++v) t.offset[v + 1] += t.offset[v];
  t.neighbours.resize(t.offset[n]);
  std::vector<std::uint32_t> fill(t.offset.begin(), t.offset.end() - 1);
  for (const auto& [a, b] : edges) {
    t.neighbours[fill[a]++] = b;
    t.neighbours[fill[b]++] = a;
  }
  return t;
}

}  // namespace nbs::detail
