#pragma once
/// \file
/// Enclosure test for the unseen-loop ĉ_m (ours, PlannerSetting::coverage_estimate = unseen_loops): is a point
/// walled in by measured surface, so that no viewpoint above the support plane can see it? The fan of the border
/// loop where an object stands on its support (Sec. 4.1: the object stands on the plane at the bottom of the box)
/// lies inside the object, under its scanned shell; that loop is no missing surface a scan could add.
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
/// detail::upper_directions() meets an occupied voxel of `space` (PlanningSpace::cast_ray: unknown and free voxels
/// do not block; a ray that leaves the space is free). Stops at the first free ray. reach_m should span the space
/// (e.g. its bounding-box diagonal). Cost: up to 17 ray casts of at most reach_m / resolution voxels each.
/// Thread-safety: only reads `space`.
template <PlanningSpace Space>
[[nodiscard]] bool enclosed_by_surface(const Space& space, const Vec3& x, double reach_m) {
  const auto all = [](const auto&...) { return true; };
  for (const Vec3& d : detail::upper_directions())
    if (!space.cast_ray(Ray{x, x + reach_m * d}, all).hit) return false;
  return true;
}

}  // namespace nbs
