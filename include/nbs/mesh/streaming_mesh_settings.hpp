// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// What configures and what reports a StreamingMesh (streaming_mesh.hpp): StreamingMeshSettings (the radii R_r, R_n,
/// R_m of Tab. 4.3 and our options), InsertResult (the fate of one point) and StreamingStats (stream counters).
/// Units: metres.

#include <cstdint>

#include "nbs/core/error.hpp"
#include "nbs/core/parameters.hpp"
#include "nbs/core/types.hpp"
#include "nbs/mesh/detail/normal_estimation.hpp"
#include "nbs/mesh/detail/spatial_hash.hpp"

namespace nbs {

/// Settings of the streaming reconstruction. Radii from `Parameters` (Tab. 4.3); the rest are our choices.
struct StreamingMeshSettings {
  double reduction_radius_m = 0.0005;  ///< R_r.
  double normal_radius_m = 0.004;      ///< R_n.
  double mesh_radius_m = 0.006;        ///< R_m.
  Aabb pass_through;                   ///< bounding box of the unknown area; empty box = no filter.
  detail::NormalRobustness robustness; ///< when a PCA normal counts as robust.
  double min_normal_dot = 0.5;         ///< vertices/faces with normals more than 60° apart are not connected.
  /// Depth of the density limitation along the line of sight (ours; 0, the default, is the thesis's R_r ball only).
  /// A point is also rejected if a stored point that faces its sensor lies within R_r of its line of sight and
  /// within this depth along it. Meant for range noise above R_r (Eq. 4.39: σ ≈ 1.1 mm at 0.3 m against R_r =
  /// 0.5 mm): the ball alone then keeps a slab of noisy layers whose tangent-plane triangulations overlap; the
  /// cylinder keeps one layer. R_n is a good value. Use with `project_vertices`.
  double density_depth_m = 0.0;
  /// Move a vertex onto the plane of its weighted PCA (through the ball's weighted mean, along its normal) when it
  /// gets its robust normal (ours, off by default: a one-step MLS projection). Triangulation and `position()` use the
  /// projected point; the density limitation and the normal stage keep the measured one (`stored_position()`).
  /// Measured with both options (density_depth_m = R_n) on a 60 mm plane at σ = 1 mm, 3 scans: triangles projected
  /// on the plane cover 1.03× its area (3–4× without) and the vertex RMS error is 0.43 mm; on the bunny (C_H, 30
  /// scans) the vertex RMS error drops from 1.07 to 0.66 mm with half the vertices. Off here (the thesis's stream as
  /// written); on in NoiseRobustStreamingMesh and in a planner's StreamingMesh by default (PlannerSetting::
  /// noise_robust_mesh, with coverage_estimate = unseen_open).
  bool project_vertices = false;

  [[nodiscard]] static StreamingMeshSettings from(const Parameters& p, const Aabb& unknown_area = {}) {
    p.validate();
    StreamingMeshSettings s;
    s.reduction_radius_m = p.reduction_radius_m;
    s.normal_radius_m = p.normal_radius_m;
    s.mesh_radius_m = p.mesh_radius_m;
    s.pass_through = unknown_area;
    return s;
  }
  /// Edge of the spatial hash's cells: R_m / 2.
  [[nodiscard]] double hash_cell_m() const { return mesh_radius_m / 2.0; }
  /// Largest |coordinate| (m, each axis) a point may have: the spatial hash's range at hash_cell_m() (±1.57 km at
  /// the default R_m = 6 mm). Farther points would share clamped cells and make insertion quadratic.
  [[nodiscard]] double max_abs_coordinate_m() const { return detail::SpatialHash::max_abs_coordinate(hash_cell_m()); }
  /// Throws InvalidArgument naming the first bad field.
  void validate() const {
    detail::require_mesh_radii(reduction_radius_m, normal_radius_m, mesh_radius_m);
    detail::require(robustness.min_neighbours >= 3, "robustness.min_neighbours must be >= 3, got ",
                    robustness.min_neighbours);
    detail::require_in_range("min_normal_dot", min_normal_dot, -1.0, 1.0);
    detail::require_in_range("density_depth_m", density_depth_m, 0.0, normal_radius_m);
  }
};

/// What happened to one incoming point.
enum class InsertResult : std::uint8_t {
  outside,        ///< outside the pass-through box: skipped.
  too_close,      ///< closer than R_r to a stored point: skipped (density limitation).
  pending,        ///< stored, normal not (yet) robust: not a mesh vertex yet.
  meshed,         ///< stored with a robust normal and triangulated.
};

/// Counters of the stream (all since construction).
struct StreamingStats {
  std::uint64_t received = 0;       ///< points insert() took (it throws on invalid ones).
  std::uint64_t outside = 0;        ///< skipped by the pass-through filter.
  std::uint64_t too_close = 0;      ///< skipped by the density limitation.
  std::uint64_t stored = 0;         ///< points kept (= vertex_count()).
  std::uint64_t meshed = 0;         ///< points with a robust normal, passed to triangulation.
  std::uint64_t normal_failures = 0;///< normal estimations that were not robust (collinear, too few neighbours...).
};

}  // namespace nbs
