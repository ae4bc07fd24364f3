// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// OrientedPoints (positions + unit normals, index-aligned), their validation and a deterministic grid subsampling.

#include <cmath>
#include <string_view>
#include <vector>

#include "nbs/core/detail/cell_key.hpp"
#include "nbs/core/error.hpp"
#include "nbs/core/types.hpp"
#include "nbs/mesh/indexed_mesh.hpp"
#include "nbs/sim/surface_samples.hpp"

namespace nbs {

/// Points with normals, index-aligned; one frame, metres; normals of unit length.
struct OrientedPoints {
  std::vector<Vec3> points;
  std::vector<Vec3> normals;

  [[nodiscard]] std::size_t size() const { return points.size(); }

  /// Throws InvalidArgument naming `what` if empty, if the normals are missing or not index-aligned, or if a point
  /// is not finite or a normal is not finite with length in [0.9, 1.1] (zero normals included).
  void validate(std::string_view what) const {
    detail::require(!points.empty(), what, ": no points");
    detail::require(!normals.empty(), what, ": no normals (", points.size(), " points; oriented points are needed)");
    detail::require(normals.size() == points.size(), what, ": ", normals.size(), " normals for ", points.size(),
                    " points");
    for (std::size_t i = 0; i < points.size(); ++i) {
      detail::require(points[i].allFinite(), what, ": point ", i, " is not finite (", points[i].x(), ", ",
                      points[i].y(), ", ", points[i].z(), ")");
      const double len = normals[i].norm();
      detail::require(std::isfinite(len) && len >= 0.9 && len <= 1.1, what, ": normal ", i,
                      " must be a unit vector, its length is ", len);
    }
  }
};

/// The oriented points of surface samples (e.g. of a database mesh, sim/surface_samples.hpp).
[[nodiscard]] inline OrientedPoints oriented_points(const SurfaceSamples& s) { return {s.points, s.normals}; }

/// The vertices of `mesh` that have a unit normal (length in [0.9, 1.1]; a streaming mesh leaves some without one),
/// with their normals, as OrientedPoints (e.g. a model from to_indexed_mesh). Throws InvalidArgument if the mesh has
/// no normals or no vertex keeps one.
[[nodiscard]] inline OrientedPoints oriented_points(const IndexedMesh& mesh) {
  detail::require(!mesh.normals.empty() && mesh.normals.size() == mesh.vertices.size(), "oriented_points: the mesh has ",
                  mesh.normals.size(), " normals for ", mesh.vertices.size(), " vertices");
  OrientedPoints p;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    const double len = mesh.normals[v].norm();
    if (!(len >= 0.9 && len <= 1.1) || !mesh.vertices[v].allFinite()) continue;
    p.points.push_back(mesh.vertices[v]);
    p.normals.push_back(mesh.normals[v] / len);
  }
  p.validate("oriented_points: mesh");
  return p;
}

/// The first point (in input order) of every occupied cell of the grid of edge `step_m`, in input order: any two
/// kept points lie in different cells. Deterministic. Precondition: `in` validated; throws InvalidArgument if
/// step_m is not finite and > 0 or a cell does not pack (coordinates beyond 2²⁰ steps).
[[nodiscard]] inline OrientedPoints grid_subsample(const OrientedPoints& in, double step_m) {
  detail::require_positive("grid_subsample: step_m", step_m);
  detail::CellKeyMap cells(in.size());
  OrientedPoints out;
  for (std::size_t i = 0; i < in.size(); ++i) {
    const std::uint64_t key = detail::pack_cell_key_checked(in.points[i] / step_m, "grid_subsample");
    if (!cells.try_emplace(key, static_cast<std::uint32_t>(i)).second) continue;
    out.points.push_back(in.points[i]);
    out.normals.push_back(in.normals[i].normalized());
  }
  return out;
}

}  // namespace nbs
