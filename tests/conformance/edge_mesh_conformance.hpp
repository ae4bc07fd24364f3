// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Conformance harness for nbs::EdgeMesh (include/nbs/mesh/mesh_concept.hpp), with its optional capabilities.
// Checked contract:
//  - positions finite; normals unit or zero;
//  - for_each_edge visits each undirected edge once, as a→b with a < b, and left/right agree with left_vertex(a, b)
//    and left_vertex(b, a) (the right of a→b is the left of b→a); is_border() is Eq. 4.1 (exactly one side);
//  - for_each_face visits face_count() faces, each once; for a face (a, b, c), c = left_vertex(a, b),
//    a = left_vertex(b, c), b = left_vertex(c, a); the edges of the faces are exactly the edges of for_each_edge,
//    and an edge is a border edge iff exactly one face holds it;
//  - faces are counter-clockwise around the normals: (b − a) × (c − a) · (n_a + n_b + n_c) > 0 for all but
//    `max_clockwise_share` of the faces whose vertices have normals (StreamingMesh normals come from noisy PCA);
//  - KnowsFaceBorders: face(f) is the f-th face of for_each_face and border_mask(f) bit k ⇔ (t[k], t[k+1]) twinless;
//  - ListsCurrentFaces: an edge is in_current_scan iff one of for_each_current_face's faces holds it.
#include "nbs_catch.hpp"

#include <algorithm>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "nbs/mesh/mesh_concept.hpp"

namespace nbs::conformance {

template <class M>
void check_edge_mesh_conformance(const M& mesh, double max_clockwise_share = 0.0) {
  static_assert(EdgeMesh<M>);
  using Edge = std::pair<VertexId, VertexId>;
  const auto undirected = [](VertexId a, VertexId b) { return a < b ? Edge{a, b} : Edge{b, a}; };
  const std::size_t nv = mesh.vertex_count();
  for (VertexId v = 0; v < nv; ++v) {
    REQUIRE(Vec3(mesh.position(v)).allFinite());
    const double n = Vec3(mesh.normal(v)).norm();
    REQUIRE((n == 0.0 || std::abs(n - 1.0) < 1e-6));
  }
  // Faces.
  std::vector<MeshFace> faces;
  mesh.for_each_face([&](const MeshFace& f) { faces.push_back(f); });
  REQUIRE(faces.size() == mesh.face_count());
  std::set<std::array<VertexId, 3>> canonical;
  std::map<Edge, int> face_edges;
  std::size_t clockwise = 0, judged = 0;
  for (const MeshFace& f : faces) {
    const std::array<VertexId, 3> t{f.a, f.b, f.c};
    for (VertexId v : t) REQUIRE(v < nv);
    REQUIRE((f.a != f.b && f.b != f.c && f.a != f.c));
    auto rot = t;
    std::rotate(rot.begin(), std::min_element(rot.begin(), rot.end()), rot.end());
    REQUIRE(canonical.insert(rot).second);  // each face once
    for (int k = 0; k < 3; ++k) {
      INFO("face (" << f.a << ", " << f.b << ", " << f.c << ") edge " << k);
      REQUIRE(mesh.left_vertex(t[k], t[(k + 1) % 3]) == t[(k + 2) % 3]);
      ++face_edges[undirected(t[k], t[(k + 1) % 3])];
    }
    const Vec3 n = Vec3(mesh.normal(f.a)) + Vec3(mesh.normal(f.b)) + Vec3(mesh.normal(f.c));
    if (Vec3(mesh.normal(f.a)).norm() == 0.0 || Vec3(mesh.normal(f.b)).norm() == 0.0 ||
        Vec3(mesh.normal(f.c)).norm() == 0.0)
      continue;
    ++judged;
    const Vec3 a = mesh.position(f.a);
    clockwise += (Vec3(mesh.position(f.b)) - a).cross(Vec3(mesh.position(f.c)) - a).dot(n) > 0.0 ? 0 : 1;
  }
  INFO(clockwise << " of " << judged << " faces with normals are clockwise around them");
  CHECK(static_cast<double>(clockwise) <= max_clockwise_share * static_cast<double>(judged));
  // Edges.
  std::set<Edge> edges;
  std::size_t borders = 0;
  mesh.for_each_edge([&](const MeshEdge& e) {
    INFO("edge " << e.a << " -> " << e.b << " left " << e.left << " right " << e.right);
    REQUIRE(e.a < e.b);
    REQUIRE(e.b < nv);
    REQUIRE(edges.insert({e.a, e.b}).second);  // once
    REQUIRE(e.left == mesh.left_vertex(e.a, e.b));
    REQUIRE(e.right == mesh.left_vertex(e.b, e.a));
    REQUIRE((e.left != kNoVertex || e.right != kNoVertex));  // an edge belongs to a face
    const auto it = face_edges.find({e.a, e.b});
    REQUIRE(it != face_edges.end());
    REQUIRE(e.is_border() == (it->second == 1));  // Eq. 4.1
    REQUIRE(e.is_border() == ((e.left == kNoVertex) != (e.right == kNoVertex)));
    borders += e.is_border() ? 1 : 0;
  });
  REQUIRE(edges.size() == face_edges.size());
  std::size_t single = 0;
  for (const auto& [e, n] : face_edges) single += n == 1 ? 1 : 0;
  CHECK(borders == single);
  if constexpr (KnowsFaceBorders<M>) {
    for (std::size_t f = 0; f < faces.size(); ++f) {
      const MeshFace g = mesh.face(f);
      REQUIRE((g.a == faces[f].a && g.b == faces[f].b && g.c == faces[f].c));
      const std::array<VertexId, 3> t{g.a, g.b, g.c};
      for (unsigned k = 0; k < 3; ++k)
        REQUIRE(((mesh.border_mask(f) >> k) & 1u) == (mesh.left_vertex(t[(k + 1) % 3], t[k]) == kNoVertex ? 1u : 0u));
    }
  }
  if constexpr (ListsCurrentFaces<M>) {
    std::set<Edge> current;
    mesh.for_each_current_face([&](const MeshFace& f) {
      current.insert(undirected(f.a, f.b));
      current.insert(undirected(f.b, f.c));
      current.insert(undirected(f.c, f.a));
    });
    mesh.for_each_edge([&](const MeshEdge& e) { REQUIRE(mesh.in_current_scan(e) == current.count({e.a, e.b}) > 0); });
  }
}

}  // namespace nbs::conformance
