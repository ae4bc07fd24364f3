// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// FCL-based `CollisionChecker` (Sec. 3.2.2, Sec. 4.5.2): the sensor head box against (a) the obstacle voxels of a
/// ProbabilisticVoxelSpace — p > 0.05, i.e. occupied or unknown, inside the bounding box of the unknown area —
/// as an `fcl::OcTree` over the `octomap::OcTree` of nbs::octomap::to_obstacle_octree, and (b) the static scene
/// (pedestal, table) as FCL boxes. Same semantics as the core nbs::VoxelCollisionChecker (touching counts up to
/// FCL's tolerances). Swept paths: nbs::collision_free_fraction (10 mm portions) accepts this checker.

#include <fcl/geometry/octree/octree.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

#include "nbs/candidates/collision.hpp"
#include "nbs/octomap/obstacle_model.hpp"

namespace nbs::fcl {

/// FCL collision checker. Takes a snapshot of the space's obstacles at construction (or `update`): later changes
/// of the space are not seen until `update` is called. Thread-safety: const members may run concurrently.
class FclCollisionChecker {
public:
  using Setting = CollisionSetting;

  /// Builds the obstacle model of `space`. Throws InvalidArgument on an invalid setting or if the bounding box of
  /// the unknown area holds more than `max_voxels` voxels or exceeds OctoMap's key range (to_obstacle_octree).
  template <class B, class M>
  FclCollisionChecker(const ProbabilisticVoxelSpace<B, M>& space, Setting setting,
                      std::uint64_t max_voxels = 50'000'000)
      : setting_(std::move(setting)), max_voxels_(max_voxels) {
    setting_.validate();
    std::erase_if(setting_.static_scene, [](const Aabb& b) { return b.empty(); });
    const Vec3 size = setting_.head.size_m;
    head_ = std::make_shared<::fcl::Boxd>(size.x(), size.y(), size.z());
    for (const Aabb& b : setting_.static_scene) {
      const Vec3 e = b.max - b.min;
      statics_.push_back({std::make_shared<::fcl::Boxd>(e.x(), e.y(), e.z()), translation(b.center())});
    }
    update(space);
  }

  /// Rebuilds the voxel obstacles from `space` (same rules). Not thread-safe against concurrent queries.
  template <class B, class M>
  void update(const ProbabilisticVoxelSpace<B, M>& space) {
    std::shared_ptr<const ::octomap::OcTree> tree =
        octomap::to_obstacle_octree(space, setting_.obstacle_probability, max_voxels_);
    octree_ = std::make_shared<::fcl::OcTreed>(tree);
  }

  [[nodiscard]] const Setting& setting() const { return setting_; }

  /// True if the head at T_WS (sensor → world) overlaps an obstacle voxel or a static box. Throws
  /// InvalidArgument unless T_WS is a finite rigid transform.
  [[nodiscard]] bool collides(const Pose& T_WS) const {
    validate_pose(T_WS, "FclCollisionChecker pose");
    const ::fcl::Transform3d tf = head_transform(T_WS);
    if (collide(*octree_, ::fcl::Transform3d::Identity(), tf)) return true;
    return std::ranges::any_of(statics_, [&](const Static& s) { return collide(*s.box, s.tf, tf); });
  }

  /// Distance (m) from the head at T_WS to the nearest obstacle voxel or static box; 0 if it collides, +∞ if there
  /// is no obstacle. Throws InvalidArgument unless T_WS is a finite rigid transform.
  [[nodiscard]] double distance(const Pose& T_WS) const {
    if (collides(T_WS)) return 0.0;
    const ::fcl::Transform3d tf = head_transform(T_WS);
    double d = distance(*octree_, ::fcl::Transform3d::Identity(), tf);
    for (const Static& s : statics_) d = std::min(d, distance(*s.box, s.tf, tf));
    return std::max(d, 0.0);
  }

private:
  struct Static {
    std::shared_ptr<::fcl::Boxd> box;
    ::fcl::Transform3d tf;
  };

  static ::fcl::Transform3d translation(const Vec3& t) {
    ::fcl::Transform3d tf = ::fcl::Transform3d::Identity();
    tf.translation() = t;
    return tf;
  }
  ::fcl::Transform3d head_transform(const Pose& T_WS) const {
    ::fcl::Transform3d tf = ::fcl::Transform3d::Identity();
    tf.linear() = T_WS.linear();
    tf.translation() = T_WS * setting_.head.center_m;
    return tf;
  }
  bool collide(const ::fcl::CollisionGeometryd& g, const ::fcl::Transform3d& g_tf,
               const ::fcl::Transform3d& head_tf) const {
    ::fcl::CollisionRequestd request;
    ::fcl::CollisionResultd result;
    ::fcl::collide(&g, g_tf, head_.get(), head_tf, request, result);
    return result.isCollision();
  }
  double distance(const ::fcl::CollisionGeometryd& g, const ::fcl::Transform3d& g_tf,
                  const ::fcl::Transform3d& head_tf) const {
    ::fcl::DistanceRequestd request;
    ::fcl::DistanceResultd result;
    result.min_distance = std::numeric_limits<double>::infinity();
    ::fcl::distance(&g, g_tf, head_.get(), head_tf, request, result);
    return result.min_distance;
  }

  Setting setting_;
  std::uint64_t max_voxels_;
  std::shared_ptr<::fcl::Boxd> head_;
  std::vector<Static> statics_;
  std::shared_ptr<::fcl::OcTreed> octree_;
};

}  // namespace nbs::fcl
