// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The edge-mesh concept of Sec. 3.3.1 (Fig. 3.9): vertices with normals and directed edges, each carrying the
/// vertices v_l / v_r that close its left and right triangles. Faces are derived from the edges.
///
/// Orientation: "left of a→b" is judged looking at the surface from the side the vertex normals point to (the
/// sensor side). A face (a, b, c) is stored counter-clockwise around its normal, so c is the left vertex of a→b.

#include <concepts>
#include <cstdint>
#include <limits>

#include "nbs/core/types.hpp"

namespace nbs {

/// Index of a vertex in a mesh.
using VertexId = std::uint32_t;
/// "No vertex": the side of an edge that has no triangle.
inline constexpr VertexId kNoVertex = std::numeric_limits<VertexId>::max();

/// One undirected edge, reported once, directed a→b with a < b (Fig. 3.9).
struct MeshEdge {
  VertexId a = kNoVertex;      ///< v_a (start).
  VertexId b = kNoVertex;      ///< v_b (end).
  VertexId left = kNoVertex;   ///< v_l: closes the triangle on the left of a→b, or kNoVertex.
  VertexId right = kNoVertex;  ///< v_r: closes the triangle on the right of a→b, or kNoVertex.

  /// Border edge, Eq. (4.1): exactly one of v_l, v_r exists.
  [[nodiscard]] bool is_border() const { return (left == kNoVertex) != (right == kNoVertex); }
};

/// A triangle (a, b, c), counter-clockwise around the surface normal.
struct MeshFace {
  VertexId a = kNoVertex, b = kNoVertex, c = kNoVertex;
};

/// Edge mesh (Sec. 3.3.1). Coordinates in metres, world frame; normals unit length (zero for a vertex without a
/// robust normal). `for_each_edge` visits every edge exactly once; `for_each_face` every triangle exactly once.
/// `left_vertex(a, b)` is the vertex closing the triangle to the left of a→b, or kNoVertex.
template <class M>
concept EdgeMesh = requires(const M& m, VertexId v, void (*edge_fn)(const MeshEdge&),
                            void (*face_fn)(const MeshFace&)) {
  { m.vertex_count() } -> std::convertible_to<std::size_t>;
  { m.position(v) } -> std::convertible_to<Vec3>;
  { m.normal(v) } -> std::convertible_to<Vec3>;
  { m.face_count() } -> std::convertible_to<std::size_t>;
  { m.left_vertex(v, v) } -> std::convertible_to<VertexId>;
  m.for_each_edge(edge_fn);
  m.for_each_face(face_fn);
};

/// Optional capability: the mesh tracks M_cur, the part touched by the current scan (Sec. 4.2).
template <class M>
concept TracksCurrentScan = EdgeMesh<M> && requires(const M& m, const MeshEdge& e) {
  { m.in_current_scan(e) } -> std::convertible_to<bool>;
};

/// Optional capability: the mesh lists the faces created or changed in the current scan (M_cur's faces, in
/// for_each_face order): an edge is in M_cur iff one of these faces holds it.
template <class M>
concept ListsCurrentFaces = TracksCurrentScan<M> && requires(const M& m, void (*face_fn)(const MeshFace&)) {
  m.for_each_current_face(face_fn);
};

/// Optional capability: per-face border bits, face(f) being the f-th face of for_each_face: bit k of
/// border_mask(f) is set iff the edge (t[k], t[k+1]) of f = (t[0], t[1], t[2]) has no twin (left_vertex(t[k+1], t[k])
/// == kNoVertex), so border tests need no adjacency lookup.
template <class M>
concept KnowsFaceBorders = EdgeMesh<M> && requires(const M& m, std::size_t f) {
  { m.face(f) } -> std::convertible_to<MeshFace>;
  { m.border_mask(f) } -> std::convertible_to<unsigned>;
};

/// Capability of an EdgeMesh that fuses a colour per vertex (Sec. 5.3): `has_colors()` is true once it holds colour,
/// then `color(v)` is vertex v's fused 8-bit RGB colour (StreamingMesh: the mean of the measurements, see there).
template <class M>
concept ColoredMesh = EdgeMesh<M> && requires(const M& m, VertexId v) {
  { m.has_colors() } -> std::convertible_to<bool>;
  { m.color(v) } -> std::convertible_to<Rgb>;
};

}  // namespace nbs
