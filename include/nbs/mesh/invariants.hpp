// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Consistency checker for any EdgeMesh: used by the tests and, through NBS_MESH_DEBUG_CHECK, in debug builds.
/// Checks: finite vertices; normals unit or zero; faces with three distinct valid vertices; no two faces on the same
/// vertex set; every directed edge in at most one face (so an undirected edge has ≤ 2 triangles, consistently
/// oriented); `for_each_edge` reports every edge exactly once with v_l / v_r equal to the faces' third vertices and
/// `left_vertex` agreeing; no two vertices closer than `min_distance_m` (R_r; 0 skips the check), measured at
/// `stored_position(v)` where the mesh has it (the measured point before projection), else at `position(v)`.
/// Cost O(V + F) expected (hash grid for the distance check).

#include <algorithm>
#include <array>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/mesh/detail/border_graph.hpp"
#include "nbs/mesh/detail/spatial_hash.hpp"
#include "nbs/mesh/mesh_concept.hpp"

namespace nbs {

/// Result of `check_invariants`: empty `problems` means consistent. Only the first few problems are described.
struct InvariantReport {
  std::size_t problem_count = 0;
  std::string problems;
  [[nodiscard]] bool ok() const { return problem_count == 0; }
  void add(const std::string& what) {
    if (++problem_count <= 10) problems += what + "\n";
  }
};

template <EdgeMesh M>
[[nodiscard]] InvariantReport check_invariants(const M& mesh, double min_distance_m = 0.0) {
  InvariantReport r;
  const std::size_t n = mesh.vertex_count();
  for (std::size_t v = 0; v < n; ++v) {
    const auto id = static_cast<VertexId>(v);
    const Vec3 p = mesh.position(id);
    const Vec3 nr = mesh.normal(id);
    if (!p.allFinite()) r.add(detail::concat("vertex ", v, " is not finite"));
    const double len = nr.norm();
    if (!(len == 0.0 || std::abs(len - 1.0) < 1e-6)) r.add(detail::concat("vertex ", v, " normal has length ", len));
  }
  auto key = [](VertexId a, VertexId b) { return (static_cast<std::uint64_t>(a) << 32) | b; };
  std::unordered_map<std::uint64_t, VertexId> directed;  // a→b → third vertex
  std::unordered_set<std::string> face_sets;
  std::size_t faces = 0;
  mesh.for_each_face([&](const MeshFace& f) {
    ++faces;
    const std::array<VertexId, 3> t{f.a, f.b, f.c};
    if (f.a >= n || f.b >= n || f.c >= n) {
      r.add(detail::concat("face (", f.a, ",", f.b, ",", f.c, ") has an invalid vertex"));
      return;
    }
    if (f.a == f.b || f.b == f.c || f.a == f.c) r.add(detail::concat("face (", f.a, ",", f.b, ",", f.c, ") repeats a vertex"));
    auto s = t;
    std::sort(s.begin(), s.end());
    if (!face_sets.insert(detail::concat(s[0], ",", s[1], ",", s[2])).second)
      r.add(detail::concat("duplicate face on vertices ", s[0], ",", s[1], ",", s[2]));
    for (int k = 0; k < 3; ++k) {
      if (!directed.emplace(key(t[k], t[(k + 1) % 3]), t[(k + 2) % 3]).second)
        r.add(detail::concat("directed edge ", t[k], "->", t[(k + 1) % 3], " is in two faces (non-manifold)"));
    }
  });
  if (faces != mesh.face_count()) r.add(detail::concat("face_count() = ", mesh.face_count(), " but ", faces, " faces visited"));
  auto third = [&](VertexId a, VertexId b) {
    const auto it = directed.find(key(a, b));
    return it == directed.end() ? kNoVertex : it->second;
  };
  std::unordered_set<std::uint64_t> seen;
  mesh.for_each_edge([&](const MeshEdge& e) {
    const VertexId lo = std::min(e.a, e.b), hi = std::max(e.a, e.b);
    if (!seen.insert(key(lo, hi)).second) r.add(detail::concat("edge ", lo, "-", hi, " reported twice"));
    if (e.left != third(e.a, e.b) || e.right != third(e.b, e.a))
      r.add(detail::concat("edge ", e.a, "->", e.b, " has v_l/v_r ", e.left, "/", e.right, " but faces say ",
                           third(e.a, e.b), "/", third(e.b, e.a)));
    if (mesh.left_vertex(e.a, e.b) != e.left || mesh.left_vertex(e.b, e.a) != e.right)
      r.add(detail::concat("left_vertex disagrees with for_each_edge on ", e.a, "->", e.b));
    if (e.left == kNoVertex && e.right == kNoVertex) r.add(detail::concat("edge ", e.a, "-", e.b, " has no triangle"));
  });
  if constexpr (detail::BorderEnumerating<M>) {  // the border enumeration equals for_each_edge's border, in order
    std::vector<MeshEdge> border, listed;
    mesh.for_each_edge([&](const MeshEdge& e) {
      if (e.is_border()) border.push_back(e);
    });
    mesh.for_each_border_edge([&](const MeshEdge& e) { listed.push_back(e); });
    const auto same = [](const MeshEdge& x, const MeshEdge& y) {
      return x.a == y.a && x.b == y.b && x.left == y.left && x.right == y.right;
    };
    if (!std::equal(border.begin(), border.end(), listed.begin(), listed.end(), same))
      r.add(detail::concat("for_each_border_edge lists ", listed.size(), " edges, for_each_edge has ", border.size(),
                           " border edges (or in another order)"));
  }
  for (const auto& [k, c] : directed) {
    (void)c;
    const auto a = static_cast<VertexId>(k >> 32), b = static_cast<VertexId>(k & 0xFFFFFFFFu);
    if (!seen.count(key(std::min(a, b), std::max(a, b)))) r.add(detail::concat("edge ", a, "-", b, " never reported"));
  }
  if (min_distance_m > 0.0 && n > 0) {
    detail::SpatialHash grid(min_distance_m);
    const double r2 = min_distance_m * min_distance_m;
    for (std::size_t v = 0; v < n; ++v) {
      // The density limitation bounds the measured points; a mesh that moves its vertices keeps them apart.
      const Vec3 p = [&] {
        if constexpr (requires { mesh.stored_position(VertexId{}); })
          return Vec3(mesh.stored_position(static_cast<VertexId>(v)));
        else
          return Vec3(mesh.position(static_cast<VertexId>(v)));
      }();
      if (!p.allFinite()) continue;
      grid.for_each_candidate(p, min_distance_m, [&](std::uint32_t q, const Vec3& pq) {
        const double d2 = (pq - p).squaredNorm();
        if (d2 < r2) r.add(detail::concat("vertices ", q, " and ", v, " are ", std::sqrt(d2), " m apart (< ", min_distance_m, ")"));
      });
      grid.insert(p, static_cast<std::uint32_t>(v));
    }
  }
  return r;
}

}  // namespace nbs

/// In debug builds (NDEBUG undefined) throws nbs::Error if `mesh` violates an invariant; no-op otherwise.
#ifndef NDEBUG
#define NBS_MESH_DEBUG_CHECK(mesh, min_distance_m)                                                    \
  do {                                                                                                \
    const auto nbs_report_ = ::nbs::check_invariants((mesh), (min_distance_m));                       \
    if (!nbs_report_.ok()) throw ::nbs::Error("mesh invariant violated:\n" + nbs_report_.problems); \
  } while (false)
#else
#define NBS_MESH_DEBUG_CHECK(mesh, min_distance_m) \
  do {                                             \
  } while (false)
#endif
