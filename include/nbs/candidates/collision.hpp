// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Collision checking of the sensor head for scan-path replanning (Sec. 4.5.2) and motion planning (Sec. 3.2.2):
/// the `CollisionChecker` concept, `NoCollisions`, the core `VoxelCollisionChecker` (sensor head box vs obstacle
/// voxels and static scene boxes) and `collision_free_fraction` (linear path in 10 mm portions).
/// The FCL-based checker lives in adapters/fcl (`nbs/fcl/collision_checker.hpp`).

#include <algorithm>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "nbs/candidates/detail/replanning_box_overlap.hpp"
#include "nbs/core/scan_path.hpp"
#include "nbs/space/concepts.hpp"
#include "nbs/space/voxel_key.hpp"

namespace nbs {

namespace detail {
/// The voxel query shared by the collision checks (VoxelCollisionChecker, robot/link_collision.hpp): visits, in
/// z-, y-, x-major order, the voxels of `space` inside its bounds (`bounds_keys()`) whose keys `grid().key_box` gives
/// for the world box `box`, calling `hit(key, cube)` (cube: the voxel's world AABB) until it returns true; returns
/// that key, or nullopt. Voxels outside the bounds are never visited (the space treats them as free).
template <VoxelSpace Space, class Hit>
[[nodiscard]] std::optional<VoxelKey> first_voxel_in(const Space& space, const Aabb& box, Hit&& hit) {
  const KeyBox bounds = space.bounds_keys();
  KeyBox kb = space.grid().key_box(box);
  if (kb.empty() || bounds.empty()) return std::nullopt;
  for (int a = 0; a < 3; ++a) {
    kb.min[a] = std::max(kb.min[a], bounds.min[a]);
    kb.max[a] = std::min(kb.max[a], bounds.max[a]);
  }
  if (kb.empty()) return std::nullopt;
  const double l = space.grid().resolution_m();
  for (std::int32_t z = kb.min.z; z <= kb.max.z; ++z)
    for (std::int32_t y = kb.min.y; y <= kb.max.y; ++y)
      for (std::int32_t x = kb.min.x; x <= kb.max.x; ++x) {
        const VoxelKey k{x, y, z};
        const Vec3 lo(x * l, y * l, z * l);
        if (hit(k, Aabb{lo, lo + Vec3::Constant(l)})) return k;
      }
  return std::nullopt;
}
}  // namespace detail

/// C tells whether the sensor head at pose T_WS (sensor → world, metres) collides with the environment.
/// `collides` is const and may throw InvalidArgument for a non-finite or non-rigid pose.
/// Models: NoCollisions, VoxelCollisionChecker, nbs::fcl::FclCollisionChecker.
template <class C>
concept CollisionChecker = requires(const C& c, const Pose& p) {
  { c.collides(p) } -> std::convertible_to<bool>;
};

/// A checker for an empty, infinite workspace (the thesis simulation, Sec. 4.7): nothing ever collides.
struct NoCollisions {
  [[nodiscard]] bool collides(const Pose&) const { return false; }
};

/// The sensor head as a box fixed in the sensor frame S (metres). The default (10 × 6 × 12 cm behind the optical
/// centre, i.e. at −s_z) is our choice for a compact laser stripe profiler; the thesis gives no dimensions.
struct SensorHeadBox {
  Vec3 center_m = Vec3(0.0, 0.0, -0.06);  ///< box centre in S
  Vec3 size_m = Vec3(0.10, 0.06, 0.12);   ///< full edge lengths along s_x, s_y, s_z (each ≥ 0)

  /// Throws InvalidArgument unless the centre is finite and every size is finite and ≥ 0.
  void validate() const {
    validate_finite(center_m, "SensorHeadBox.center_m");
    detail::require(size_m.allFinite() && (size_m.array() >= 0.0).all(),
                    "SensorHeadBox.size_m must be finite and >= 0, got (", size_m.transpose(), ")");
  }
  /// The box in the world for sensor pose T_WS (not validated).
  [[nodiscard]] detail::OrientedBox at(const Pose& T_WS) const {
    return {T_WS * center_m, T_WS.linear(), 0.5 * size_m};
  }
};

/// What the sensor head must not touch (Sec. 3.2.2). Shared by VoxelCollisionChecker and nbs::fcl.
struct CollisionSetting {
  SensorHeadBox head{};
  std::vector<Aabb> static_scene{};    ///< world AABBs (pedestal, table, ...); empty boxes are ignored
  double obstacle_probability = 0.05;  ///< voxels with p above this are obstacles (Sec. 3.2.2)

  /// Throws InvalidArgument naming the bad field.
  void validate() const {
    head.validate();
    for (std::size_t i = 0; i < static_scene.size(); ++i)
      detail::require(static_scene[i].empty() || (static_scene[i].min.allFinite() && static_scene[i].max.allFinite()),
                      "static_scene box ", i, " is not finite");
    detail::require_in_range("obstacle_probability", obstacle_probability, 0.0, 1.0);
  }
};

/// Core collision checker (Sec. 3.2.2): the sensor head box collides if it overlaps (touching counts)
///  - a voxel inside the bounding box of the unknown area with p > `obstacle_probability` (occupied *or unknown*:
///    an unknown voxel has p = 0.5; voxels outside that box are free), or
///  - one of the static scene boxes (world AABBs, e.g. pedestal and table below z = 0).
/// Holds a reference to the space: it must outlive the checker and not change while `collides` runs.
/// Thread-safety: `collides` is const and may run concurrently. Cost: one p look-up per voxel of the head's world
/// AABB (clipped to the bounds), an exact box test only for obstacle voxels; stops at the first collision.
template <VoxelSpace Space>
class VoxelCollisionChecker {
public:
  using Setting = CollisionSetting;

  /// Throws InvalidArgument if the setting is invalid.
  VoxelCollisionChecker(const Space& space, Setting setting) : space_(&space), setting_(std::move(setting)) {
    setting_.validate();
    std::erase_if(setting_.static_scene, [](const Aabb& b) { return b.empty(); });
  }

  [[nodiscard]] const Setting& setting() const { return setting_; }

  /// True if the head at T_WS collides. Throws InvalidArgument unless T_WS is a finite rigid transform.
  [[nodiscard]] bool collides(const Pose& T_WS) const {
    validate_pose(T_WS, "VoxelCollisionChecker pose");
    const detail::OrientedBox box = setting_.head.at(T_WS);
    return collides_static(box) || collides_voxels(box);
  }
  /// The static-scene part of collides() only.
  [[nodiscard]] bool collides_static(const detail::OrientedBox& box) const {
    return std::ranges::any_of(setting_.static_scene, [&](const Aabb& b) { return detail::overlaps(box, b); });
  }
  /// The voxel part of collides() only.
  [[nodiscard]] bool collides_voxels(const detail::OrientedBox& box) const {
    return detail::first_voxel_in(*space_, box.bounds(), [&](const VoxelKey& k, const Aabb& cube) {
             return space_->probability(k) > setting_.obstacle_probability && detail::overlaps(box, cube);
           }).has_value();
  }

private:
  const Space* space_;
  Setting setting_;
};

/// Number of 10 mm portions (Sec. 3.2.2) of a path of length `length_m`: ⌈length / portion⌉, at least 1.
[[nodiscard]] inline std::size_t path_portions(double length_m, double portion_m) {
  detail::require_positive("portion_m", portion_m);
  detail::require_non_negative("path length", length_m);
  const double n = std::ceil(length_m / portion_m - 1e-9);
  detail::require(n < 1e7, "path of ", length_m, " m needs too many portions of ", portion_m, " m");
  return std::max<std::size_t>(1, static_cast<std::size_t>(n));
}

/// Fraction of collision-free portions of a linear scan path (Sec. 3.2.2, Sec. 4.5.2): the path is cut into
/// n = path_portions(length, portion_m) equal portions; portion k is free if the poses at k/n and (k+1)/n are
/// (each pose checked once). A zero-length path is one pose: 1 if it is free, else 0. Result in [0, 1].
/// Throws InvalidArgument if portion_m is not > 0 (and whatever `checker.collides` throws).
template <CollisionChecker Checker>
[[nodiscard]] double collision_free_fraction(const Checker& checker, const LinearScanPath& path,
                                             double portion_m = 0.01) {
  const std::size_t n = path_portions(path.length(), portion_m);
  if (path.length() == 0.0) return checker.collides(path.pose_at(0.0)) ? 0.0 : 1.0;
  std::size_t free = 0;
  bool prev_free = !checker.collides(path.pose_at(0.0));
  for (std::size_t k = 1; k <= n; ++k) {
    const bool cur_free = !checker.collides(path.pose_at(static_cast<double>(k) / static_cast<double>(n)));
    free += (prev_free && cur_free) ? 1 : 0;
    prev_free = cur_free;
  }
  return static_cast<double>(free) / static_cast<double>(n);
}

}  // namespace nbs
