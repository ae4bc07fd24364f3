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

template <EdgeMesh M>
[[nodiscard]] MeshTopology mesh_topology(const M& mesh) {
  const std::size_t n = mesh.vertex_count();
  MeshTopology t;
  t.offset.assign(n + 1, 0);
  t.triangulated.assign(n, 0);
  // One pass over the edges (each may cost the mesh a lookup), kept in order for the fill below.
  std::vector<std::pair<VertexId, VertexId>> edges;
  mesh.for_each_edge([&](const MeshEdge& e) {
    if (e.a >= n || e.b >= n) return;
    ++t.offset[e.a + 1];
    ++t.offset[e.b + 1];
    edges.emplace_back(e.a, e.b);
  });
  for (std::size_t v = 0; v < n; ++v) t.offset[v + 1] += t.offset[v];
  t.neighbours.resize(t.offset[n]);
  std::vector<std::uint32_t> fill(t.offset.begin(), t.offset.end() - 1);
  for (const auto& [a, b] : edges) {
    t.neighbours[fill[a]++] = b;
    t.neighbours[fill[b]++] = a;
  }
  mesh.for_each_face([&](const MeshFace& f) {
    for (VertexId v : {f.a, f.b, f.c})
      if (v < n) t.triangulated[v] = 1;
  });
  return t;
}

}  // namespace nbs::detail
