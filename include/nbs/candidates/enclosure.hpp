// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Enclosure test for the unseen-loop ĉ_m (ours, UnseenLoopCoverage with the enclosure test, the form unseen_open): is a point walled
/// in by measured surface? The fan of the border loop where an object stands on its support (Sec. 4.1: the object
/// stands on the plane at the bottom of the box) lies inside the object, under its scanned shell; that loop is no
/// missing surface a scan could add. The test samples 17 fixed directions, so an opening that none of them passes
/// through (e.g. a narrow one ≈ 27° off an axis) is not seen: the point then counts as enclosed.
///
/// With `LowViews` (the form observable_open) the test also looks slightly downward, where a sensor standing above the
/// support can still look from: under an overhang high above the support (a mushroom's cap, a table top) the fan of
/// the overhang's border loop is walled in above and at the sides, yet a low sensor sees under it (c_obs counts that
/// surface: sim/observability.hpp admits every sensor above the support plane).
///
/// Frames: world (types.hpp), +z up; the support plane is horizontal below every tested point.

#include <array>
#include <cmath>
#include <numbers>
#include <optional>

#include "nbs/candidates/planning_context.hpp"
#include "nbs/core/types.hpp"

namespace nbs {

namespace detail {
/// The 17 unit directions (a, b, c)/|(a, b, c)| with a, b, c ∈ {−1, 0, 1}, c ≥ 0, not all zero: the upper half of
/// the 3×3×3 neighbourhood (the lower half meets the support plane).
[[nodiscard]] inline const std::array<Vec3, 17>& upper_directions() {
  static const std::array<Vec3, 17> dirs = [] {
    std::array<Vec3, 17> d{};
    std::size_t n = 0;
    for (int c = 0; c <= 1; ++c)
      for (int b = -1; b <= 1; ++b)
        for (int a = -1; a <= 1; ++a)
          if ((a != 0 || b != 0 || c != 0) && n < d.size())
            d[n++] = Vec3(a, b, c).normalized();
    return d;
  }();
  return dirs;
}
/// The 33 downward unit directions: 8 azimuths (multiples of 45°) at elevations −5°, −10°, −20° and −35°, shallow
/// first, then straight down.
[[nodiscard]] inline const std::array<Vec3, 33>& lower_directions() {
  static const std::array<Vec3, 33> dirs = [] {
    std::array<Vec3, 33> d{};
    std::size_t n = 0;
    for (const double elevation_deg : {5.0, 10.0, 20.0, 35.0})
      for (int a = 0; a < 8; ++a) {
        const double az = a * std::numbers::pi / 4.0, el = elevation_deg * std::numbers::pi / 180.0;
        d[n++] = Vec3(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), -std::sin(el));
      }
    d[n] = Vec3(0, 0, -1);
    return d;
  }();
  return dirs;
}
}  // namespace detail

/// Where a sensor may look from below (enclosed_by_surface's lower directions): a sensor `view_distance_m` from the
/// point must stand strictly above the support plane z = `support_z` (world, m). 0.15 m is the DLR LSP's near range,
/// the distance c_obs places its sensors at (ObservabilitySettings::min_range_m). The rays themselves run the full
/// reach like the upward ones, so measured surface beyond that sensor position also blocks them: with the support
/// measured into the space (a real table under the object) every admissible downward ray ends on it and the test is
/// the upward one; crop the support's points first.
struct LowViews {
  double support_z = 0.0;
  double view_distance_m = 0.15;
};

/// True if every ray from `x` (world, m) of length `reach_m` along the 17 upward and horizontal directions of
/// detail::upper_directions() meets an occupied voxel of `space` (VoxelSpace::cast_ray: unknown and free voxels
/// do not block; a ray that leaves the space is free). Stops at the first free ray. reach_m should span the space
/// (e.g. its bounding-box diagonal). Cost: up to 17 ray casts of at most reach_m / resolution voxels each.
/// Thread-safety: only reads `space`.
template <VoxelSpace Space>
[[nodiscard]] bool enclosed_by_surface(const Space& space, const Vec3& x, double reach_m) {
  for (const Vec3& d : detail::upper_directions())
    if (!space.cast_ray(Ray{x, x + reach_m * d}, detail::ContinueVisit{}).hit) return false;
  return true;
}

/// enclosed_by_surface, and also every ray along a detail::lower_directions() direction d from which a sensor would
/// stand above the support (x_z + low.view_distance_m · d_z > low.support_z) meets an occupied voxel within reach_m.
/// A point on the support (x_z − support_z < view_distance_m · sin 5°, 1.3 cm at 0.15 m) is tested as by
/// enclosed_by_surface. Cost: up to 17 + 33 ray casts. Thread-safety: only reads `space`.
template <VoxelSpace Space>
[[nodiscard]] bool enclosed_by_surface(const Space& space, const Vec3& x, double reach_m, const LowViews& low) {
  if (!enclosed_by_surface(space, x, reach_m)) return false;
  for (const Vec3& d : detail::lower_directions()) {
    if (!(x.z() + low.view_distance_m * d.z() > low.support_z)) continue;  // that sensor would stand in the support
    if (!space.cast_ray(Ray{x, x + reach_m * d}, detail::ContinueVisit{}).hit) return false;
  }
  return true;
}

/// The `seen(x)` predicate of estimated_coverage_unseen as the planner uses it: x lies in a voxel with
/// p > `occupied_threshold` or, with `with_enclosure` (CoverageEstimate::unseen_open, unknown_open, observable_open),
/// it is enclosed_by_surface with rays of `reach_m` — also looking down as `low` says if given (observable_open).
/// Holds a reference to `space`.
template <class Space>
[[nodiscard]] auto surface_seen(const Space& space, double occupied_threshold, double reach_m, bool with_enclosure,
                                std::optional<LowViews> low = std::nullopt) {
  return [&space, occupied_threshold, reach_m, with_enclosure, low](const Vec3& x) {
    if (space.probability(x) > occupied_threshold) return true;
    if (!with_enclosure) return false;
    return low ? enclosed_by_surface(space, x, reach_m, *low) : enclosed_by_surface(space, x, reach_m);
  };
}

}  // namespace nbs
