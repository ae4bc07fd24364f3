// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The planning ray cast of the VoxelSpace contract written once for any space: `walk_ray_generic(space, ray,
/// visit)` looks up each voxel's state with `space.state(key)`. A user-written space forwards its `cast_ray` to it;
/// ProbabilisticVoxelSpace uses it unless its backend is a BlockBackend (then it walks block by block, same voxels).

#include <type_traits>
#include <utility>

#include "nbs/core/error.hpp"
#include "nbs/space/detail/segment_clip.hpp"
#include "nbs/space/detail/segment_walker.hpp"
#include "nbs/space/space_types.hpp"

namespace nbs {

namespace detail {
/// One voxel of a planning cast: counts it, calls visit(key, state) (false stops the cast; a visitor returning
/// void never stops it), records a hit at an occupied voxel. Returns whether the walk goes on.
template <class Visit, class State>
bool ray_step(RaycastResult& res, Visit& visit, const VoxelKey& k, const State& s, bool occupied) {
  ++res.voxels;
  if constexpr (std::is_convertible_v<std::invoke_result_t<Visit&, const VoxelKey&, const State&>, bool>) {
    if (!visit(k, s)) return false;
  } else {
    visit(k, s);
  }
  if (occupied) {
    res.hit = true;
    res.hit_key = k;
    return false;
  }
  return true;
}

/// Throws InvalidArgument unless both end points of ray `i` are finite.
inline void check_ray(const Ray& r, std::size_t i) {
  require(r.origin.allFinite() && r.end.allFinite(), "ray ", i, " is not finite: origin (", r.origin.transpose(),
          ") end (", r.end.transpose(), ")");
}

/// The segment of `ray` inside `vbounds`, in voxel units (world · inv); false if the ray misses the box.
inline bool clip_ray(const Ray& ray, const Aabb& vbounds, double inv, Vec3& a, Vec3& b) {
  double t0, t1;
  if (!clip_segment(ray.origin, ray.end, vbounds, t0, t1)) return false;
  a = point_in_box(ray.origin, ray.end, t0, vbounds) * inv;
  b = point_in_box(ray.origin, ray.end, t1, vbounds) * inv;
  return true;
}
}  // namespace detail

namespace detail {
/// walk_ray_generic without the finiteness check of the ray (the caller has checked it).
template <class Space, class Visit>
RaycastResult walk_ray_unchecked(const Space& space, const Ray& ray, Visit& visit) {
  RaycastResult res;
  Vec3 a, b;
  if (!clip_ray(ray, space.voxel_bounds(), space.grid().inverse_resolution(), a, b)) return res;
  const auto& model = space.model();
  SegmentWalker w(a, b);
  for (;;) {
    const VoxelKey k = w.key();
    const auto s = space.state(k);
    if (!ray_step(res, visit, k, s, model.occupied(s))) break;
    if (w.remaining() == 0) break;
    w.step();
  }
  return res;
}
}  // namespace detail

/// Visits the voxels on `ray` inside space.voxel_bounds(), in order from the origin, calling visit(key, state) for
/// each (unknown voxels included, as State{}); stops after the first occupied voxel (hit) or when visit returns
/// false. A ray that misses voxel_bounds() visits nothing. Throws InvalidArgument if the ray is not finite.
/// Needs of `space`: voxel_bounds(), grid(), state(key), model().occupied(state).
template <class Space, class Visit>
RaycastResult walk_ray_generic(const Space& space, const Ray& ray, Visit&& visit) {
  detail::check_ray(ray, 0);
  return detail::walk_ray_unchecked(space, ray, visit);
}

}  // namespace nbs
