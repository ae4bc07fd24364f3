// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Test helper: a rigid pose from a rotation and a translation.
#include "nbs/core/types.hpp"

namespace nbs_test {

/// T with T.linear() = R and T.translation() = t (R is taken as given: pass a rotation).
inline nbs::Pose rigid_pose(const nbs::Mat3& R, const nbs::Vec3& t) {
  nbs::Pose T = nbs::Pose::Identity();
  T.linear() = R;
  T.translation() = t;
  return T;
}

}  // namespace nbs_test
