// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Linear scan path (Sec. 4.3.2): the sensor keeps one orientation and moves on a straight line from S_1 to S_2.

#include <algorithm>

#include "nbs/core/viewpoint.hpp"

namespace nbs {

/// A linear scan path: two viewpoints S_1, S_2 sharing one rotation (Sec. 4.3.2, Fig. 4.9).
/// A zero-length path is a single viewpoint (used for area sensors).
/// Invariant: both poses are valid rigid transforms with the same rotation.
class LinearScanPath {
public:
  LinearScanPath() = default;

  /// Path from `start` (orientation and s_p^1) to the position `end_position` (s_p^2), metres.
  LinearScanPath(const Viewpoint& start, const Vec3& end_position) : start_(start), end_position_(end_position) {
    validate_finite(end_position, "scan path end position");
  }

  /// Single-viewpoint path (length 0).
  explicit LinearScanPath(const Viewpoint& v) : start_(v), end_position_(v.position()) {}

  [[nodiscard]] const Viewpoint& start() const { return start_; }
  [[nodiscard]] Viewpoint end() const {
    Pose p = start_.pose();
    p.translation() = end_position_;
    return Viewpoint(p);
  }
  /// Path length |s_p^2 − s_p^1| in metres.
  [[nodiscard]] double length() const { return (end_position_ - start_.position()).norm(); }
  /// Sensor pose at arc-length fraction t ∈ [0, 1] (clamped).
  [[nodiscard]] Pose pose_at(double t) const {
    t = std::clamp(t, 0.0, 1.0);
    Pose p = start_.pose();
    p.translation() = (1.0 - t) * start_.position() + t * end_position_;
    return p;
  }
  [[nodiscard]] const Vec3& end_position() const { return end_position_; }

private:
  Viewpoint start_;
  Vec3 end_position_ = Vec3::Zero();
};

}  // namespace nbs
