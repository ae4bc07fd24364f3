// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Border edges (Eq. 4.1) of an EdgeMesh, directed so that their triangle lies on the left, with per-vertex
/// outgoing / incoming lists for walking along the mesh border.

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "nbs/mesh/mesh_concept.hpp"

namespace nbs::detail {

/// Meshes that enumerate their border edges directly, in for_each_edge order (StreamingMesh).
template <class M>
concept BorderEnumerating = requires(const M& m, void (*fn)(const MeshEdge&)) { m.for_each_border_edge(fn); };

struct BorderGraph {
  struct Edge {
    VertexId from, to;  ///< triangle on the left of from→to
    bool current;       ///< e ∈ M_cur (always true for meshes that do not track scans)
  };
  /// Edges of one vertex (ids into `edges`, in the order of `edges`), stored compressed over all vertices.
  struct Lists {
    std::vector<std::uint32_t> offset;  ///< vertex v's edges are ids[offset[v] .. offset[v + 1])
    std::vector<std::uint32_t> ids;
  };
  std::vector<Edge> edges;  ///< border edges in for_each_edge order
  Lists out, in;            ///< per vertex: border edges leaving / entering it

  template <EdgeMesh M>
  explicit BorderGraph(const M& mesh) {
    const std::size_t n = mesh.vertex_count();
    const auto add = [&](const MeshEdge& e) {
      if (!e.is_border() || e.a >= n || e.b >= n) return;  // ids ≥ n: not a vertex of the mesh
      bool cur = true;
      if constexpr (TracksCurrentScan<M>) cur = mesh.in_current_scan(e);
      edges.push_back(e.left != kNoVertex ? Edge{e.a, e.b, cur} : Edge{e.b, e.a, cur});
    };
    if constexpr (BorderEnumerating<M>) {
      mesh.for_each_border_edge(add);
    } else {
      mesh.for_each_edge(add);
    }
    out = lists(n, [](const Edge& e) { return e.from; });
    in = lists(n, [](const Edge& e) { return e.to; });
  }

  /// First edge of `list` at v accepted by `ok`, or -1.
  template <class Ok>
  [[nodiscard]] std::int64_t pick(const Lists& list, VertexId v, Ok&& ok) const {
    if (static_cast<std::size_t>(v) + 1 >= list.offset.size()) return -1;
    for (std::uint32_t i = list.offset[v]; i < list.offset[v + 1]; ++i)
      if (ok(list.ids[i])) return list.ids[i];
    return -1;
  }

private:
  // Counting sort of the edge ids by vertex(e), stable (ids of one vertex stay in edge order).
  template <class VertexOf>
  [[nodiscard]] Lists lists(std::size_t n, VertexOf&& vertex_of) const {
    Lists l;
    l.offset.assign(n + 1, 0);
    for (const Edge& e : edges) ++l.offset[static_cast<std::size_t>(vertex_of(e)) + 1];
    for (std::size_t v = 0; v < n; ++v) l.offset[v + 1] += l.offset[v];
    l.ids.resize(edges.size());
    std::vector<std::uint32_t> fill(l.offset.begin(), l.offset.end() - 1);
    for (std::uint32_t id = 0; id < edges.size(); ++id) l.ids[fill[vertex_of(edges[id])]++] = id;
    return l;
  }
};

}  // namespace nbs::detail
