// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The unknown-area boxes the voxel-space tests share (one definition, so the test files also build as one unit).

#include "nbs/core/types.hpp"

namespace nbs_test {
/// A cube of side 0.1998 m about the origin (just inside ±0.1 m, so no voxel straddles the bound at 2 mm or 5 mm).
inline const nbs::Aabb kCubeBox{nbs::Vec3::Constant(-0.0999), nbs::Vec3::Constant(0.0999)};
/// 0.2 × 0.2 × 0.2 m standing on z = 0 (the flushing tests).
inline const nbs::Aabb kFlushBox{nbs::Vec3(-0.1, -0.1, 0.0), nbs::Vec3(0.1, 0.1, 0.2)};
}  // namespace nbs_test
