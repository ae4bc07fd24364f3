// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// `GrippedDriver`: the `ScanDriver` the planner drives for a gripped object (Sec. 5.4). Poses are sensor poses in
/// the object frame O (gripped/gripped_object.hpp). It forwards to an `inner` driver that works in O — a simulation
/// of object + fingers (`SimulatedDriver` over a scanner of gripped_scene_mesh), or a hardware driver that commands
/// the arm to object_pose_for(T_BS, T_OS) and maps its data with scan_in_object_frame — removes the finger points
/// from every scan (remove_finger_points) and records the object poses T_BO of Eq. 5.1 the robot takes.

#include <cstddef>
#include <utility>
#include <vector>

#include "nbs/driver/concepts.hpp"
#include "nbs/gripped/gripped_object.hpp"

namespace nbs {

/// Holds a reference to `inner` (it must outlive the driver) and a copy of the set-up. Not thread-safe.
template <ScanDriver Inner>
class GrippedDriver {
public:
  /// Throws InvalidArgument (naming the field) if the set-up is invalid.
  GrippedDriver(Inner& inner, GrippedSetup setup) : inner_(&inner), setup_(std::move(setup)) { setup_.validate(); }

  /// Eq. 5.1 for `T_OS` (InvalidArgument for a non-rigid pose, nothing changed), then the inner move_to.
  void move_to(const Pose& T_OS) {
    const Pose T_BO = object_pose_for(setup_.T_BS, T_OS);
    inner_->move_to(T_OS);
    object_pose_ = T_BO;
  }

  /// The object's linear motion for `path` (object_path_for, recorded), the inner scan, its finger points removed.
  /// Throws what the inner driver throws (nothing recorded then).
  [[nodiscard]] Scan acquire(const LinearScanPath& path) {
    const ObjectPath op = object_path_for(setup_.T_BS, path);
    Scan scan = inner_->acquire(path);
    const std::size_t removed = remove_finger_points(setup_, scan);
    removed_ += removed;
    object_paths_.push_back(op);
    object_pose_ = op.end;
    return scan;
  }

  /// The current sensor pose in O (the inner driver's).
  [[nodiscard]] Pose current_pose() const { return inner_->current_pose(); }
  /// The object pose T_BO (Eq. 5.1) of the last move_to or scan end (identity before the first).
  [[nodiscard]] const Pose& object_pose() const { return object_pose_; }
  /// The object's motion per acquired scan, in order.
  [[nodiscard]] const std::vector<ObjectPath>& object_paths() const { return object_paths_; }
  /// Finger points removed over all scans.
  [[nodiscard]] std::size_t removed_points() const { return removed_; }
  [[nodiscard]] const GrippedSetup& setup() const { return setup_; }

private:
  Inner* inner_;
  GrippedSetup setup_;
  Pose object_pose_ = Pose::Identity();
  std::vector<ObjectPath> object_paths_;
  std::size_t removed_ = 0;
};

}  // namespace nbs
