// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Parameters of the NBS method with the defaults of Tab. 4.3 (thesis simulation), SI units.
/// Fields the thesis leaves open carry a documented choice of ours and say so.

#include <numbers>

#include "nbs/core/error.hpp"

namespace nbs {
namespace detail {
/// The radii of the streaming mesh (Sec. 3.3.1): each finite and > 0, and R_r below R_n and R_m (the density
/// limitation must leave points for the normal ball and the triangulation). Names both values of a broken order.
inline void require_mesh_radii(double reduction_radius_m, double normal_radius_m, double mesh_radius_m) {
  require_positive("reduction_radius_m", reduction_radius_m);
  require_positive("normal_radius_m", normal_radius_m);
  require_positive("mesh_radius_m", mesh_radius_m);
  require(reduction_radius_m < normal_radius_m, "reduction_radius_m (", reduction_radius_m,
          ") must be smaller than normal_radius_m (", normal_radius_m, ")");
  require(reduction_radius_m < mesh_radius_m, "reduction_radius_m (", reduction_radius_m,
          ") must be smaller than mesh_radius_m (", mesh_radius_m, ")");
}
}  // namespace detail

/// Every tunable of mesh generation, voxel space, candidate generation, selection and termination.
/// Defaults reproduce Tab. 4.3 and Sec. 4.7. Call `validate()` before use; components do so at construction.
struct Parameters {
  // --- Streaming mesh generation (Sec. 3.3.1) -----------------------------------------------------------------
  double reduction_radius_m = 0.0005;  ///< R_r: density limitation; a point closer than this to a vertex is dropped.
  double normal_radius_m = 0.004;      ///< R_n: radius of the weighted-PCA normal estimation ball.
  double mesh_radius_m = 0.006;        ///< R_m: radius of the localized triangulation neighbourhood.

  // --- Probabilistic voxel space (Sec. 3.3.2) ---------------------------------------------------------------------
  double voxel_size_m = 0.005;         ///< l_v: voxel edge length.
  /// p ≥ this: a voxel holding mesh vertices gets surface features (Sec. 4.5.1). The thesis uses 0.95 with its
  /// sensor model; in nbs a voxel is updated at most once per scan (beam independence) with P_hit = 0.7, so 0.95
  /// would need four agreeing scans and the quality term (Eq. 4.33) would see no surface in the first scans, when
  /// it matters most. 0.6 accepts one hit, even after one later free measurement (p ≈ 0.61). Our deviation.
  double occupied_threshold = 0.6;

  // --- Boundary Search (Sec. 4.2, 4.3) ----------------------------------------------------------------------------
  int boundary_penalty_threshold = 5;  ///< ρ_t: consecutive badly aligned edges before a boundary walk aborts.
  int min_boundary_edges = 15;         ///< b_min: minimum number of border edges of a boundary.
  double boundary_angle_rad = std::numbers::pi / 4.0;  ///< α_t = 45°: edge/sensor-axis angle threshold (Tab. 4.1).
  double scan_overlap = 0.3;           ///< o (Eq. 4.14): overlap of a candidate's FOV with the mesh. Our choice; the
                                       ///< thesis gives no number.
  double planar_eigenvalue_max = 0.09; ///< λ₂, λ₃ ≤ this: boundary region is planar (sharp-corner rule, Sec. 4.3.1).
  double sharp_corner_rotation_rad = std::numbers::pi / 4.0;  ///< rotation about the boundary for sharp corners.

  // --- Hole Rescan (Sec. 4.4) -------------------------------------------------------------------------------------
  int hole_min_edges = 3;              ///< h_min: smallest hole of interest (edges). Our choice.
  int hole_max_edges = 200;            ///< h_max: largest hole of interest (edges). Our choice.
  int hole_directions = 200;           ///< directions sampled per hole in Alg. 2.

  // --- NBS selection (Sec. 4.5.3) ---------------------------------------------------------------------------------
  double quality_weight = 0.7;         ///< λ: surface quality weight in q_s (Eq. 4.33), Tab. 4.3.
  double quality_half_scans = 5.0;     ///< n_q in ω(n_s) = n_s / (n_s + n_q) (Eq. 4.31).
  double incidence_cutoff_rad = 70.0 * std::numbers::pi / 180.0;  ///< beams with larger incidence are not counted.

  // --- Process control / termination (Sec. 4.6) -------------------------------------------------------------------
  double target_coverage = 0.80;       ///< ĉ_m: the thesis's rule stops when the estimated coverage reaches this (Tab. 4.3).
  double target_density = 0.20;        ///< d̄_m: ... and the mean relative density this (Tab. 4.3; also the settled rule's).
  int max_scans = 30;                  ///< n_abort: hard limit on the number of scans (Tab. 4.3).
  double mode_switch_gain = 0.01;      ///< switch BS → HR when ĉ_m grows by less than this per scan (Eq. 4.38).

  // --- Evaluation (Sec. 4.7) --------------------------------------------------------------------------------------
  double object_size_m = 0.16;         ///< largest bounding-box extent of the benchmark object (Sec. 4.7).
  double completeness_radius_m = 0.003;  ///< r: ground-truth sample counts as covered within this distance.
  double sphere_path_length_m = 0.30;  ///< length of each of the 81 sphere-baseline scan paths (Sec. 4.7.2).

  /// Throws InvalidArgument naming the first field outside its domain.
  void validate() const {
    using detail::require;
    using detail::require_in_range;
    using detail::require_positive;
    detail::require_mesh_radii(reduction_radius_m, normal_radius_m, mesh_radius_m);
    require_positive("voxel_size_m", voxel_size_m);
    require_in_range("occupied_threshold", occupied_threshold, 0.5, 1.0);
    require(boundary_penalty_threshold >= 0, "boundary_penalty_threshold must be >= 0, got ",
            boundary_penalty_threshold);
    require(min_boundary_edges >= 2, "min_boundary_edges must be >= 2, got ", min_boundary_edges);
    require_in_range("boundary_angle_rad", boundary_angle_rad, 0.0, std::numbers::pi / 2.0);
    require_in_range("scan_overlap", scan_overlap, 0.0, 1.0);
    require_in_range("planar_eigenvalue_max", planar_eigenvalue_max, 0.0, 1.0);
    require_in_range("sharp_corner_rotation_rad", sharp_corner_rotation_rad, 0.0, std::numbers::pi / 2.0);
    require(hole_min_edges >= 3 && hole_max_edges >= hole_min_edges, "hole edge limits must satisfy 3 <= h_min (",
            hole_min_edges, ") <= h_max (", hole_max_edges, ")");
    require(hole_directions >= 1, "hole_directions must be >= 1, got ", hole_directions);
    require_in_range("quality_weight", quality_weight, 0.0, 1.0);
    require_positive("quality_half_scans", quality_half_scans);
    require_in_range("incidence_cutoff_rad", incidence_cutoff_rad, 0.0, std::numbers::pi / 2.0);
    require_in_range("target_coverage", target_coverage, 0.0, 1.0);
    require_in_range("target_density", target_density, 0.0, 1.0);
    require(max_scans >= 1, "max_scans must be >= 1, got ", max_scans);
    require_in_range("mode_switch_gain", mode_switch_gain, 0.0, 1.0);
    require_positive("object_size_m", object_size_m);
    require(voxel_size_m < object_size_m, "voxel_size_m (", voxel_size_m, ") must be smaller than object_size_m (",
            object_size_m, ")");
    require_positive("completeness_radius_m", completeness_radius_m);
    require_positive("sphere_path_length_m", sphere_path_length_m);
  }
};

}  // namespace nbs
