// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Topology and geometry counts of a loaded mesh, and a loader that can refuse non-manifold input.

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/io/load_mesh.hpp"
#include "nbs/mesh/indexed_mesh.hpp"

namespace nbs {

/// Counts describing a mesh. Edges are undirected vertex pairs {a, b} with a != b.
struct LoadReport {
  std::size_t vertices = 0;              ///< \#V.
  std::size_t faces = 0;                 ///< \#F.
  std::size_t zero_area_faces = 0;       ///< faces with |(b−a)×(c−a)| == 0 (includes repeated indices).
  std::size_t duplicate_faces = 0;       ///< faces whose vertex set equals that of an earlier face.
  std::size_t non_manifold_edges = 0;    ///< edges used by more than 2 faces.
  std::size_t boundary_edges = 0;        ///< edges used by exactly 1 face.
  std::size_t unreferenced_vertices = 0; ///< vertices no face uses.
  std::size_t inconsistent_edges = 0;    ///< edges used by exactly 2 faces that traverse it in the same direction.
};

/// Counts of `mesh`. Throws InvalidArgument if a triangle index is >= \#V. O(\#F) expected time; thread-safe.
[[nodiscard]] inline LoadReport inspect_mesh(const IndexedMesh& mesh) {
  const std::size_t nv = mesh.vertices.size();
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k)
      detail::require(mesh.triangles[t][static_cast<std::size_t>(k)] < nv, "inspect_mesh: triangle ", t,
                      " has vertex index ", mesh.triangles[t][static_cast<std::size_t>(k)], " >= vertex count ", nv);

  LoadReport r;
  r.vertices = nv;
  r.faces = mesh.triangles.size();
  std::vector<bool> used(nv, false);
  struct EdgeUse {
    std::size_t faces = 0;
    long forward = 0;  // +1 per face traversing min→max, −1 per face traversing max→min.
  };
  std::unordered_map<std::uint64_t, EdgeUse> edges;
  struct FaceHash {
    std::size_t operator()(const std::array<std::uint32_t, 3>& f) const {
      return std::hash<std::uint64_t>()((std::uint64_t(f[0]) << 42) ^ (std::uint64_t(f[1]) << 21) ^ f[2]);
    }
  };
  std::unordered_set<std::array<std::uint32_t, 3>, FaceHash> seen;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& f = mesh.triangles[t];
    for (std::uint32_t v : f) used[v] = true;
    if (mesh.face_normal_scaled(t).squaredNorm() == 0.0) ++r.zero_area_faces;
    std::array<std::uint32_t, 3> key = f;
    std::sort(key.begin(), key.end());
    if (!seen.insert(key).second) ++r.duplicate_faces;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = f[static_cast<std::size_t>(k)], b = f[static_cast<std::size_t>((k + 1) % 3)];
      if (a == b) continue;
      EdgeUse& e = edges[(std::uint64_t(std::min(a, b)) << 32) | std::max(a, b)];
      ++e.faces;
      e.forward += a < b ? 1 : -1;
    }
  }
  for (const auto& [key, e] : edges) {
    if (e.faces == 1) ++r.boundary_edges;
    if (e.faces > 2) ++r.non_manifold_edges;
    if (e.faces == 2 && e.forward != 0) ++r.inconsistent_edges;
  }
  r.unreferenced_vertices = static_cast<std::size_t>(std::count(used.begin(), used.end(), false));
  return r;
}

/// Options of load_mesh_with_report.
struct LoadOptions {
  bool require_manifold = false;  ///< throw FileError if the mesh has non-manifold edges or zero-area faces.
};

/// load_mesh(path), and its inspect_mesh counts in `out`. With `options.require_manifold`, throws FileError naming
/// `path` and the counts if the mesh has non-manifold edges or zero-area faces; `out` is unchanged on any throw.
[[nodiscard]] inline IndexedMesh load_mesh_with_report(const std::string& path, LoadReport& out,
                                                       LoadOptions options = {}) {
  IndexedMesh mesh = load_mesh(path);
  const LoadReport r = inspect_mesh(mesh);
  if (options.require_manifold && (r.non_manifold_edges > 0 || r.zero_area_faces > 0))
    throw FileError(detail::concat(path, ": mesh is not manifold: ", r.non_manifold_edges,
                                   " non-manifold edges (used by > 2 faces), ", r.zero_area_faces,
                                   " zero-area faces"));
  out = r;
  return mesh;
}

}  // namespace nbs
