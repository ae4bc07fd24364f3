// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Mean relative point density d̄_m (Sec. 4.6) from the per-vertex d(v) = N_act / N_max (Eqs. 4.24–4.25).

#include <concepts>

#include "nbs/mesh/mesh_concept.hpp"

namespace nbs {

/// A mesh that knows the relative density d(v) ∈ [0, 1] of its vertices (Eq. 4.24).
template <class M>
concept DensityMesh = EdgeMesh<M> && requires(const M& m, VertexId v) {
  { m.relative_density(v) } -> std::convertible_to<double>;
};

/// d̄_m: mean of d(v) over the vertices that belong to a triangle; 0 if there are none.
template <DensityMesh M>
[[nodiscard]] double mean_relative_density(const M& mesh) {
  std::vector<char> used(mesh.vertex_count(), 0);
  mesh.for_each_face([&](const MeshFace& f) { used[f.a] = used[f.b] = used[f.c] = 1; });
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t v = 0; v < used.size(); ++v)
    if (used[v]) sum += mesh.relative_density(static_cast<VertexId>(v)), ++n;
  return n > 0 ? sum / static_cast<double>(n) : 0.0;
}

}  // namespace nbs
