// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The mesh-coverage estimate ĉ_m (Eq. 4.35) as a planner policy: concept `CoverageEstimator` and its models.
/// ĉ_m drives the termination criterion and the process control (Eq. 4.38). Every model computes
/// ĉ_m = A_filled / (A_filled + A_empty); they differ in A_empty:
/// - `ThesisCoverage`: the border loops with h_min..h_max edges, unweighted (Eqs. 4.35–4.37 as written);
/// - `UnseenLoopCoverage` (the planner's default, with `enclosure = true`; nbs's reading for noisy streams): every
///   closed border loop, each Eq. 4.37 area weighted by the share of its fan samples that are neither measured
///   surface in the voxel space (p > occupied_threshold) nor, with `enclosure`, walled in by it (enclosed_by_surface:
///   every upward and horizontal ray meets an occupied voxel). `enclosure = false` is the form `unseen_loops`.
/// - `SelectableCoverage`: one of the three chosen at run time (the runtime facade and config files use it).
/// docs/evaluation.md compares the forms. Thread-safety: `estimate` is const and only reads mesh and space.

#include <algorithm>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "nbs/candidates/enclosure.hpp"
#include "nbs/core/error.hpp"
#include "nbs/core/parameters.hpp"
#include "nbs/mesh/holes.hpp"
#include "nbs/mesh/mesh_concept.hpp"
#include "nbs/space/concepts.hpp"

namespace nbs {

/// What a coverage estimate reads: the mesh, the voxel space, the parameters and the bounding box of the unknown
/// area (world, metres). References only.
template <class Mesh, class Space>
struct CoverageInput {
  const Mesh& mesh;
  const Space& space;
  const Parameters& params;
  const Aabb& unknown_area;
};

/// ĉ_m ∈ [0, 1] and the number of holes with h_min ≤ |E_H| ≤ h_max among the loops it looked at.
struct CoverageResult {
  double coverage = 0.0;
  std::size_t holes = 0;
};

/// A ĉ_m policy: `c.estimate(CoverageInput<Mesh, Space>)` → CoverageResult (coverage clamped to [0, 1]); const,
/// deterministic, and a mesh without triangles gives 0.
template <class C, class Mesh, class Space>
concept CoverageEstimator = EdgeMesh<Mesh> && VoxelSpace<Space> && std::copy_constructible<C> &&
                            requires(const C& c, const CoverageInput<Mesh, Space>& in) {
                              { c.estimate(in) } -> std::same_as<CoverageResult>;
                            };

/// Eqs. 4.35–4.37 as written: A_empty = Σ A_hole over the holes with h_min..h_max edges (find_holes).
struct ThesisCoverage {
  struct Setting {};
  Setting setting{};
  template <EdgeMesh Mesh, VoxelSpace Space>
  [[nodiscard]] CoverageResult estimate(const CoverageInput<Mesh, Space>& in) const {
    const std::vector<Hole> holes = find_holes(in.mesh, in.params);
    return {std::clamp(estimated_coverage(in.mesh, holes), 0.0, 1.0), holes.size()};
  }
};

/// Eq. 4.35 over every closed border loop, each weighted by its unseen share (file comment).
struct UnseenLoopCoverage {
  struct Setting {
    /// Also count a fan sample as seen when it is walled in by measured surface (the form `unseen_open`; false is
    /// `unseen_loops`). The loop where the object stands on its support has its fan inside the object, under the
    /// scanned shell: no scan can add that surface (bunny, C_H, 20 runs, scan 10: ĉ_m 0.926 with, 0.735 without,
    /// at c_a = 98.1 % of c_obs).
    bool enclosure = true;
  };
  Setting setting{};

  /// The `seen(x)` predicate (world point x): x lies in a voxel with p > params.occupied_threshold or, with
  /// `enclosure`, it is enclosed_by_surface with rays spanning the unknown-area box. Holds a reference to the space.
  template <VoxelSpace Space>
  [[nodiscard]] auto seen(const Space& space, const Parameters& params, const Aabb& unknown_area) const {
    return surface_seen(space, params.occupied_threshold, (unknown_area.max - unknown_area.min).norm(),
                        setting.enclosure);
  }
  template <EdgeMesh Mesh, VoxelSpace Space>
  [[nodiscard]] CoverageResult estimate(const CoverageInput<Mesh, Space>& in) const {
    const std::vector<Hole> loops = find_all_loops(in.mesh, in.params);
    CoverageResult r;
    r.holes = static_cast<std::size_t>(std::ranges::count_if(
        loops, [&](const Hole& h) { return static_cast<int>(h.vertices.size()) <= in.params.hole_max_edges; }));
    r.coverage = std::clamp(estimated_coverage_unseen(in.mesh, loops, seen(in.space, in.params, in.unknown_area)),
                            0.0, 1.0);
    return r;
  }
};

/// The forms of ĉ_m by name, for configuration files and the runtime facade.
enum class CoverageEstimate : std::uint8_t { thesis, unseen_loops, unseen_open };

/// Names of CoverageEstimate in enum order ("thesis", "unseen_loops", "unseen_open").
inline constexpr std::string_view kCoverageEstimateNames[] = {"thesis", "unseen_loops", "unseen_open"};

/// One of the three forms, chosen at run time (`setting.form`; default unseen_open = UnseenLoopCoverage{true}).
struct SelectableCoverage {
  struct Setting {
    CoverageEstimate form = CoverageEstimate::unseen_open;
  };
  Setting setting{};
  /// UnseenLoopCoverage::seen of the form (the enclosure test with unseen_open only); the thesis form uses none.
  template <VoxelSpace Space>
  [[nodiscard]] auto seen(const Space& space, const Parameters& params, const Aabb& unknown_area) const {
    return UnseenLoopCoverage{{setting.form == CoverageEstimate::unseen_open}}.seen(space, params, unknown_area);
  }
  template <EdgeMesh Mesh, VoxelSpace Space>
  [[nodiscard]] CoverageResult estimate(const CoverageInput<Mesh, Space>& in) const {
    switch (setting.form) {
      case CoverageEstimate::thesis: return ThesisCoverage{}.estimate(in);
      case CoverageEstimate::unseen_loops: return UnseenLoopCoverage{{false}}.estimate(in);
      case CoverageEstimate::unseen_open: return UnseenLoopCoverage{{true}}.estimate(in);
    }
    detail::require(false, "SelectableCoverage: unknown form ", static_cast<int>(setting.form));
    return {};
  }
};

}  // namespace nbs
