// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Clipping of a segment to an axis-aligned box (the planning casts and the update walks clip to voxel_bounds()).

#include <algorithm>
#include <utility>

#include "nbs/core/types.hpp"

namespace nbs::detail {

/// Clips the segment a → b to the closed box (Liang–Barsky). Returns false if they do not meet; otherwise sets
/// [t0, t1] ⊆ [0, 1].
inline bool clip_segment(const Vec3& a, const Vec3& b, const Aabb& box, double& t0, double& t1) {
  t0 = 0.0;
  t1 = 1.0;
  for (int i = 0; i < 3; ++i) {
    const double d = b[i] - a[i];
    if (d == 0.0) {
      if (a[i] < box.min[i] || a[i] > box.max[i]) return false;
      continue;
    }
    double ta = (box.min[i] - a[i]) / d;
    double tb = (box.max[i] - a[i]) / d;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

/// a + t·(b − a), clamped into the box (guards against round-off past the faces).
inline Vec3 point_in_box(const Vec3& a, const Vec3& b, double t, const Aabb& box) {
  return (a + t * (b - a)).cwiseMax(box.min).cwiseMin(box.max);
}

}  // namespace nbs::detail
