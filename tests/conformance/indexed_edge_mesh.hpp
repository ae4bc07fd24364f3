// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A minimal user-written EdgeMesh over an IndexedMesh (consistently oriented, manifold edges): the user model of the
// EdgeMesh conformance suite, also the mesh of the CoverageEstimator suite.
#include <algorithm>
#include <map>
#include <utility>

#include "nbs/mesh/indexed_mesh.hpp"
#include "nbs/mesh/mesh_concept.hpp"

namespace nbs::conformance {

/// The user-written edge mesh: an IndexedMesh (consistently oriented, manifold edges) with a directed-edge map.
class IndexedEdgeMesh {
public:
  explicit IndexedEdgeMesh(nbs::IndexedMesh m) : m_(std::move(m)) {
    for (const auto& t : m_.triangles)
      for (int k = 0; k < 3; ++k) left_[{t[k], t[(k + 1) % 3]}] = t[(k + 2) % 3];
  }
  [[nodiscard]] std::size_t vertex_count() const { return m_.vertices.size(); }
  [[nodiscard]] nbs::Vec3 position(nbs::VertexId v) const { return m_.vertices[v]; }
  [[nodiscard]] nbs::Vec3 normal(nbs::VertexId) const { return nbs::Vec3::UnitZ(); }  // a plane facing +z
  [[nodiscard]] std::size_t face_count() const { return m_.triangles.size(); }
  [[nodiscard]] nbs::VertexId left_vertex(nbs::VertexId a, nbs::VertexId b) const {
    const auto it = left_.find({a, b});
    return it == left_.end() ? nbs::kNoVertex : it->second;
  }
  template <class F>
  void for_each_edge(F&& f) const {
    for (const auto& [e, l] : left_)
      if (e.first < e.second || left_vertex(e.second, e.first) == nbs::kNoVertex) {
        const nbs::VertexId a = std::min(e.first, e.second), b = std::max(e.first, e.second);
        f(nbs::MeshEdge{a, b, left_vertex(a, b), left_vertex(b, a)});
      }
  }
  template <class F>
  void for_each_face(F&& f) const {
    for (const auto& t : m_.triangles) f(nbs::MeshFace{t[0], t[1], t[2]});
  }

private:
  nbs::IndexedMesh m_;
  std::map<std::pair<nbs::VertexId, nbs::VertexId>, nbs::VertexId> left_;
};

}  // namespace nbs::conformance
