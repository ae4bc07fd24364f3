// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The mesh-coverage estimate ĉ_m (Eq. 4.35) as a planner policy: concept `CoverageEstimator` and its models.
/// ĉ_m drives the termination criterion and the process control (Eq. 4.38). Every model computes
/// ĉ_m = A_filled / (A_filled + A_empty); they differ in A_empty:
/// - `ThesisCoverage`: the border loops with h_min..h_max edges, unweighted (Eqs. 4.35–4.37 as written);
/// - `UnseenLoopCoverage` (the planner's default; nbs's reading for noisy streams): every closed border loop, each
///   Eq. 4.37 area weighted by the share of its fan samples that are neither measured surface in the voxel space
///   (p > occupied_threshold) nor, with `enclosure`, walled in by measured surface (enclosed_by_surface: every
///   upward and horizontal ray meets an occupied voxel) nor, with `free_space`, measured free (p < free_below: a
///   beam passed through, no surface can be there) in a loop longer than h_max whose fan lies at least half in
///   free space (FreeSeamRule). Forms: `unknown_open` (both, the default), `unseen_open` (enclosure only),
///   `unseen_loops` (neither), `observable_open` (`unknown_open` whose enclosure test also looks down where a sensor
///   above the support could look from: `low_views`, LowViews).
/// - `SelectableCoverage`: one of the five chosen at run time (the runtime facade and config files use it).
/// docs/evaluation.md compares the forms. Thread-safety: `estimate` is const and only reads mesh and space.

#include <algorithm>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <optional>
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

/// ĉ_m ∈ [0, 1], the number of holes with h_min ≤ |E_H| ≤ h_max among the loops it looked at, and where the
/// estimate puts the missing surface: the Eq. 4.37 fan samples A_empty is made of (Σ area_m2 = A_empty; empty when
/// the estimator does not say). The planner hands them to the utility (UtilityContext::unseen_surface).
struct CoverageResult {
  double coverage = 0.0;
  std::size_t holes = 0;
  std::vector<UnseenSample> unseen{};
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
    CoverageResult r{std::clamp(estimated_coverage(in.mesh, holes), 0.0, 1.0), holes.size()};
    for (const Hole& h : holes) (void)fan_seen_share(in.mesh, h, [](const Vec3&) { return false; }, &r.unseen);
    return r;
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
    /// Also count the fan samples in measured-free voxels (p < free_below) as seen in a loop with more than
    /// h_max (params.hole_max_edges) edges whose fan lies at least `min_free_share` in free space: the form
    /// `unknown_open` (with `enclosure`). Such a loop is a seam winding round the object; its fan cuts through the
    /// empty space the object encloses (the mug's cavity, the space between a table's legs), 11–15 mm from the
    /// surface, and held ĉ_m at 0.37–0.47 while c_a was 97–98 % (docs/internals.md). Per sample instead of per
    /// loop it also raised ĉ_m on the bunny, spot and the teapot (small gaps are partly free) and stopped earlier.
    bool free_space = true;
    /// p below this is "measured free": under the prior 0.5, i.e. at least one beam passed through the voxel.
    double free_below = 0.45;
    /// The share of a long loop's fan samples in free space from which it counts as a seam. Measured (fan samples
    /// of loops > 200 edges): bunny ≤ 0.35, mug 0.82–0.96, table 0.42–0.69.
    double min_free_share = 0.5;
    /// With `enclosure`: a fan sample counts as walled in only if also the downward rays from which a sensor
    /// `low_view_distance_m` away would stand above the support (the bottom of the unknown-area box) meet measured
    /// surface (enclosed_by_surface with LowViews; the form `observable_open`). The fan under an overhang high above
    /// the support (a mushroom's cap, a car's body) is walled in above and at the sides, so without this it counted
    /// as seen though c_obs counts the surface there (docs/evaluation.md: with SGU_H the mushroom's median stop
    /// moves from 8 to 4 scans before k99, the car's from 20 to 8.5).
    bool low_views = false;
    double low_view_distance_m = 0.15;
  };
  Setting setting{};

  /// The per-sample `seen(x)` predicate (world point x): x lies in a voxel with p > params.occupied_threshold or,
  /// with `enclosure`, it is enclosed_by_surface with rays spanning the unknown-area box (with `low_views` also the
  /// downward rays of LowViews{unknown_area.min.z(), low_view_distance_m}). Holds a reference to the space. (The
  /// free-space rule is per loop: estimate().)
  template <VoxelSpace Space>
  [[nodiscard]] auto seen(const Space& space, const Parameters& params, const Aabb& unknown_area) const {
    std::optional<LowViews> low;
    if (setting.low_views) low = LowViews{unknown_area.min.z(), setting.low_view_distance_m};
    return surface_seen(space, params.occupied_threshold, (unknown_area.max - unknown_area.min).norm(),
                        setting.enclosure, low);
  }
  template <EdgeMesh Mesh, VoxelSpace Space>
  [[nodiscard]] CoverageResult estimate(const CoverageInput<Mesh, Space>& in) const {
    const std::vector<Hole> loops = find_all_loops(in.mesh, in.params);
    CoverageResult r;
    r.holes = static_cast<std::size_t>(std::ranges::count_if(
        loops, [&](const Hole& h) { return static_cast<int>(h.vertices.size()) <= in.params.hole_max_edges; }));
    const auto seen_x = seen(in.space, in.params, in.unknown_area);
    if (!setting.free_space) {
      r.coverage = std::clamp(estimated_coverage_unseen(in.mesh, loops, seen_x, &r.unseen), 0.0, 1.0);
      return r;
    }
    const auto free_x = [&](const Vec3& x) { return in.space.probability(x) < setting.free_below; };
    r.coverage = std::clamp(estimated_coverage_unseen_free(in.mesh, loops, seen_x, free_x,
                                                           FreeSeamRule{in.params.hole_max_edges, setting.min_free_share},
                                                           &r.unseen),
                            0.0, 1.0);
    return r;
  }
};

/// The forms of ĉ_m by name, for configuration files and the runtime facade: `thesis` (ThesisCoverage), and
/// UnseenLoopCoverage with neither test (`unseen_loops`), the enclosure test (`unseen_open`, the default until
/// issue 18), both (`unknown_open`, the default) or both with the enclosure test looking down too
/// (`observable_open`, UnseenLoopCoverage::Setting::low_views).
enum class CoverageEstimate : std::uint8_t { thesis, unseen_loops, unseen_open, unknown_open, observable_open };

/// Names of CoverageEstimate in enum order ("thesis", "unseen_loops", "unseen_open", "unknown_open",
/// "observable_open").
inline constexpr std::string_view kCoverageEstimateNames[] = {"thesis", "unseen_loops", "unseen_open",
                                                              "unknown_open", "observable_open"};

/// UnseenLoopCoverage's setting of an unseen-loop form (`form` ≠ thesis).
[[nodiscard]] constexpr UnseenLoopCoverage::Setting unseen_loop_setting(CoverageEstimate form) {
  UnseenLoopCoverage::Setting s;
  s.enclosure = form != CoverageEstimate::unseen_loops;
  s.free_space = form == CoverageEstimate::unknown_open || form == CoverageEstimate::observable_open;
  s.low_views = form == CoverageEstimate::observable_open;
  return s;
}

/// One of the five forms, chosen at run time (`setting.form`; default unknown_open = UnseenLoopCoverage{}).
struct SelectableCoverage {
  struct Setting {
    CoverageEstimate form = CoverageEstimate::unknown_open;
  };
  Setting setting{};
  /// UnseenLoopCoverage::seen of the form (occupied only for thesis and unseen_loops; the thesis form uses none; the
  /// per-loop free-space rule of unknown_open is not in it).
  template <VoxelSpace Space>
  [[nodiscard]] auto seen(const Space& space, const Parameters& params, const Aabb& unknown_area) const {
    return UnseenLoopCoverage{unseen_loop_setting(setting.form)}.seen(space, params, unknown_area);
  }
  template <EdgeMesh Mesh, VoxelSpace Space>
  [[nodiscard]] CoverageResult estimate(const CoverageInput<Mesh, Space>& in) const {
    switch (setting.form) {
      case CoverageEstimate::thesis: return ThesisCoverage{}.estimate(in);
      case CoverageEstimate::unseen_loops:
      case CoverageEstimate::unseen_open:
      case CoverageEstimate::unknown_open:
      case CoverageEstimate::observable_open:
        return UnseenLoopCoverage{unseen_loop_setting(setting.form)}.estimate(in);
    }
    detail::require(false, "SelectableCoverage: unknown form ", static_cast<int>(setting.form));
    return {};
  }
};

}  // namespace nbs
