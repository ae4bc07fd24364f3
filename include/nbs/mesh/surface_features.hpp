// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Surface features per voxel (Sec. 4.5.1): mean relative density d̄_i (Eq. 4.26), mean normal n̄_i (Eq. 4.27) and
/// border-edge share b_i (Eq. 4.28), computed from the mesh into a SurfaceFeatureMap keyed by voxel (the planner's).
/// A vertex belongs to the voxel containing it; an edge to the voxel containing its midpoint. Only vertices that
/// belong to a triangle count.

#include <algorithm>
#include <cstdint>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "nbs/core/parameters.hpp"
#include "nbs/mesh/density.hpp"
#include "nbs/space/concepts.hpp"
#include "nbs/space/key_slots.hpp"
#include "nbs/space/surface_features.hpp"
#include "nbs/space/voxel_key.hpp"

namespace nbs {

using SurfaceFeatureTable = std::unordered_map<VoxelKey, SurfaceFeatures, VoxelKeyHash>;

/// Features of the voxels of `grid` that hold a mesh vertex; when `only` is non-null, just those voxels. O(V + F)
/// with array lookups (KeySlots over the key box of the wanted voxels); twin lookups only for the edges of
/// the wanted voxels. Sums run in ascending vertex order.
template <DensityMesh M>
[[nodiscard]] SurfaceFeatureTable compute_surface_features(const M& mesh, const VoxelGrid& grid,
                                                           const std::unordered_set<VoxelKey, VoxelKeyHash>* only = nullptr) {
  struct Acc {
    VoxelKey key;
    double density = 0.0;
    Vec3 normal = Vec3::Zero();
    std::size_t vertices = 0, edges = 0, border = 0;
  };
  // Vertices in a triangle, with their voxel keys; the key box of the wanted voxels.
  std::vector<char> used(mesh.vertex_count(), 0);
  mesh.for_each_face([&](const MeshFace& f) { used[f.a] = used[f.b] = used[f.c] = 1; });
  std::vector<VoxelKey> vkey(used.size());
  KeyBox box;
  for (std::size_t i = 0; i < used.size(); ++i) {
    if (!used[i]) continue;
    const auto k = grid.key_of(mesh.position(static_cast<VertexId>(i)));
    if (!k) {
      used[i] = 0;
      continue;
    }
    vkey[i] = *k;
    if (!only) box.extend(*k);
  }
  if (only)
    for (const VoxelKey& k : *only) box.extend(k);
  constexpr std::int32_t kWanted = -2;  // a wanted voxel without a vertex yet
  KeySlots slot(box);
  if (only)
    for (const VoxelKey& k : *only) slot.assign(k, kWanted);
  std::vector<Acc> acc;
  for (std::size_t i = 0; i < used.size(); ++i) {
    if (!used[i]) continue;
    const VoxelKey& k = vkey[i];
    std::int32_t s = slot.find(k);
    if (only && s == KeySlots::kNone) continue;
    if (s < 0) {
      s = static_cast<std::int32_t>(acc.size());
      acc.push_back({k});
      slot.assign(k, s);
    }
    Acc& a = acc[static_cast<std::size_t>(s)];
    const auto v = static_cast<VertexId>(i);
    a.density += mesh.relative_density(v);
    a.normal += mesh.normal(v);
    ++a.vertices;
  }
  // The edges of for_each_edge, read off the faces: edge a→b of a face is counted there if a < b, or if no face holds
  // b→a (a border edge of this face alone). Whether b→a exists comes from the face's border bits when the mesh keeps
  // them, else from left_vertex, asked only when the midpoint's voxel has a slot.
  const auto count_edge = [&](const VertexId a, const VertexId b, auto&& has_twin) {
    const auto key = grid.key_of(0.5 * (mesh.position(a) + mesh.position(b)));
    if (!key) return;
    const std::int32_t s = slot.find(*key);
    if (s < 0) return;
    const bool twin = has_twin();
    if (a > b && twin) return;  // counted by the twin face
    Acc& e = acc[static_cast<std::size_t>(s)];
    ++e.edges;
    e.border += twin ? 0 : 1;
  };
  if constexpr (KnowsFaceBorders<M>) {
    for (std::size_t i = 0; i < mesh.face_count(); ++i) {
      const MeshFace f = mesh.face(i);
      const unsigned border = mesh.border_mask(i);
      const VertexId t[3] = {f.a, f.b, f.c};
      for (int k = 0; k < 3; ++k) count_edge(t[k], t[(k + 1) % 3], [&] { return !((border >> k) & 1u); });
    }
  } else {
    mesh.for_each_face([&](const MeshFace& f) {
      const VertexId t[3] = {f.a, f.b, f.c};
      for (int k = 0; k < 3; ++k) {
        const VertexId a = t[k], b = t[(k + 1) % 3];
        count_edge(a, b, [&] { return mesh.left_vertex(b, a) != kNoVertex; });
      }
    });
  }
  SurfaceFeatureTable out;
  out.reserve(acc.size());
  for (const Acc& a : acc) {
    SurfaceFeatures f;
    f.mean_density = static_cast<float>(std::clamp(a.density / static_cast<double>(a.vertices), 0.0, 1.0));
    Vec3 n = a.normal / static_cast<double>(a.vertices);
    if (n.norm() > 1.0) n.normalize();  // rounding only
    f.mean_normal = n.cast<float>();
    if (f.mean_normal.norm() > 1.0f) f.mean_normal /= f.mean_normal.norm() * (1.0f + 1e-6f);
    f.border_share = a.edges > 0 ? static_cast<float>(static_cast<double>(a.border) / static_cast<double>(a.edges)) : 0.0f;
    out.emplace(a.key, f);
  }
  return out;
}

/// Incremental update after a scan (Sec. 4.5.1): recomputes the features of the voxels that hold a vertex of a face
/// in M_cur and writes those whose voxel in `space` has p ≥ params.occupied_threshold into `features` (the planner
/// owns the map; the space is only read). Returns the number of voxels written.
template <VoxelSpace S, DensityMesh M>
  requires TracksCurrentScan<M>
std::size_t update_surface_features(SurfaceFeatureMap& features, const S& space, const M& mesh,
                                    const Parameters& params) {
  params.validate();
  std::unordered_set<VoxelKey, VoxelKeyHash> touched;
  if constexpr (ListsCurrentFaces<M>) {  // the vertices of M_cur's edges are those of its faces
    mesh.for_each_current_face([&](const MeshFace& f) {
      for (VertexId v : {f.a, f.b, f.c})
        if (const auto k = space.grid().key_of(mesh.position(v))) touched.insert(*k);
    });
  } else {
    mesh.for_each_edge([&](const MeshEdge& e) {
      if (!mesh.in_current_scan(e)) return;
      for (VertexId v : {e.a, e.b})
        if (const auto k = space.grid().key_of(mesh.position(v))) touched.insert(*k);
    });
  }
  std::size_t written = 0;
  for (const auto& [k, f] : compute_surface_features(mesh, space.grid(), &touched)) {
    if (space.probability(k) < params.occupied_threshold) continue;
    features.set(k, f);
    ++written;
  }
  return written;
}

}  // namespace nbs
