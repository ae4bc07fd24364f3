#pragma once
/// \file
/// Border edges (Eq. 4.1) of an EdgeMesh, directed so that their triangle lies on the left, with per-vertex
/// outgoing / incoming lists for walking along the mesh border.

#include <array>
#include <unordered_map>
#include <vector>

#include "nbs/mesh/mesh_concept.hpp"

namespace nbs::detail {

struct BorderGraph {
  struct Edge {
    VertexId from, to;  ///< triangle on the left of from→to
    bool current;       ///< e ∈ M_cur (always true for meshes that do not track scans)
  };
  std::vector<Edge> edges;
  std::unordered_map<VertexId, std::vector<std::uint32_t>> out, in;

  template <EdgeMesh M>
  explicit BorderGraph(const M& mesh) {
    mesh.for_each_edge([&](const MeshEdge& e) {
      if (!e.is_border()) return;
      bool cur = true;
      if constexpr (TracksCurrentScan<M>) cur = mesh.in_current_scan(e);
      const auto id = static_cast<std::uint32_t>(edges.size());
      const Edge d = e.left != kNoVertex ? Edge{e.a, e.b, cur} : Edge{e.b, e.a, cur};
      edges.push_back(d);
      out[d.from].push_back(id);
      in[d.to].push_back(id);
    });
  }

  /// First edge of `list[v]` accepted by `ok`, or -1.
  template <class Ok>
  [[nodiscard]] std::int64_t pick(const std::unordered_map<VertexId, std::vector<std::uint32_t>>& list, VertexId v,
                                  Ok&& ok) const {
    const auto it = list.find(v);
    if (it == list.end()) return -1;
    for (std::uint32_t e : it->second)
      if (ok(e)) return e;
    return -1;
  }
};

}  // namespace nbs::detail
