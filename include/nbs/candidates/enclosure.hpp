// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Enclosure test for the unseen-loop ĉ_m (ours, UnseenLoopCoverage with the enclosure test, the form unseen_open): is a point walled
/// in by measured surface? The fan of the border loop where an object stands on its support (Sec. 4.1: the object
/// stands on the plane at the bottom of the box) lies inside the object, under its scanned shell; that loop is no
/// missing surface a scan could add. The test samples 17 fixed directions, so an opening that none of them passes
/// through (e.g. a narrow one ≈ 27° off an axis) is not seen: the point then counts as enclosed.
///
/// Frames: world (types.hpp), +z up; the support plane is horizontal below every tested point.

#include <array>
#include <cmath>

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
}  // namespace detail

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

/// The `seen(x)` predicate of estimated_coverage_unseen as the planner uses it: x lies in a voxel with
/// p > `occupied_threshold` or, with `with_enclosure` (CoverageEstimate::unseen_open, unknown_open), it is
/// enclosed_by_surface with rays of `reach_m`. Holds a reference to `space`.
template <class Space>
[[nodiscard]] auto surface_seen(const Space& space, double occupied_threshold, double reach_m, bool with_enclosure) {
  return [&space, occupied_threshold, reach_m, with_enclosure](const Vec3& x) {
    return space.probability(x) > occupied_threshold ||
           (with_enclosure && enclosed_by_surface(space, x, reach_m));
  };
}

}  // namespace nbs
