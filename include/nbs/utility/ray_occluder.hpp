// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Occlusion of candidate rays by what lies outside the planner's unknown area: a `RayOccluder` tells the candidate
/// evaluation how much of each simulated beam is free of outside obstacles, so that a planner modeling one object
/// among others predicts that its neighbours hide it (thesis Sec. 3.1: "other objects are obstacles and occluders").
/// `VoxelSpaceOccluder` answers from a shared scene voxel space (e.g. the one nbs_explore fuses every scan into).

#include <algorithm>
#include <functional>

#include "nbs/core/error.hpp"
#include "nbs/space/concepts.hpp"
#include "nbs/space/detail/segment_clip.hpp"
#include "nbs/space/space_types.hpp"

namespace nbs {

/// f(ray) ∈ [0, 1]: the beam origin + t·(end − origin) (world frame, metres) is free of outside occluders for t < f
/// (1 = not occluded). Empty = no occluder. Called concurrently by the evaluation threads: it must be a pure
/// function of the ray (no mutable state).
using RayOccluder = std::function<double(const Ray&)>;

/// RayOccluder over `scene` (borrowed: it must outlive the occluder and not change during an evaluation that uses it):
/// a beam is cut where it enters the first occupied voxel of `scene` it meets before it enters `target` grown by
/// `margin_m`; voxels overlapping the grown target never occlude (the target's own surface). Beams that miss the
/// grown target are not cut (they see nothing of it), nor are beams starting inside it (no outside part). Unknown
/// voxels do not occlude (an optimistic prediction, as the planner's own ray casts, Sec. 4.5.3). Throws
/// InvalidArgument if target is empty or not finite, or margin_m < 0.
template <VoxelSpace Space>
class VoxelSpaceOccluder {
public:
  VoxelSpaceOccluder(const Space& scene, const Aabb& target, double margin_m = 0.0) : scene_(&scene) {
    detail::require(!target.empty() && target.min.allFinite() && target.max.allFinite(),
                    "VoxelSpaceOccluder: the target box must be finite and not empty");
    detail::require_non_negative("VoxelSpaceOccluder margin_m", margin_m);
    grown_ = Aabb{target.min - Vec3::Constant(margin_m), target.max + Vec3::Constant(margin_m)};
  }
  /// See RayOccluder. Throws InvalidArgument if the ray is not finite.
  double operator()(const Ray& ray) const {
    detail::require(ray.origin.allFinite() && ray.end.allFinite(), "VoxelSpaceOccluder: ray is not finite");
    double t0, t1;
    if (!detail::clip_segment(ray.origin, ray.end, grown_, t0, t1) || t0 <= 0.0) return 1.0;
    const Vec3 d = ray.end - ray.origin;
    const double half = 0.5 * scene_->resolution_m();
    const auto outside_target = [&](const VoxelKey& k, const auto&) {
      const Vec3 c = scene_->grid().center(k);
      return ((c.array() + half) <= grown_.min.array()).any() || ((c.array() - half) >= grown_.max.array()).any();
    };
    const RaycastResult r = scene_->cast_ray(Ray{ray.origin, ray.origin + t0 * d}, outside_target);
    if (!r.hit) return 1.0;
    // The beam's entry into the hit voxel (the cast met it, so the clip succeeds; 0 if the origin lies in it).
    const Vec3 c = scene_->grid().center(r.hit_key);
    double e0 = 0.0, e1 = 1.0;
    if (!detail::clip_segment(ray.origin, ray.end, Aabb{c - Vec3::Constant(half), c + Vec3::Constant(half)}, e0, e1))
      e0 = t0;
    return std::clamp(e0, 0.0, t0);
  }

private:
  const Space* scene_;
  Aabb grown_;
};

}  // namespace nbs
