// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Oriented box vs axis-aligned box overlap by the separating axis theorem (15 axes), for collision checks of the
/// sensor head against voxels and static scene boxes.

#include <cmath>

#include "nbs/core/types.hpp"

namespace nbs::detail {

/// A box with centre `center` (world, m), axes `axes` (columns: unit box axes in world, right-handed) and
/// half edge lengths `half` (m, ≥ 0) along those axes.
struct OrientedBox {
  Vec3 center = Vec3::Zero();
  Mat3 axes = Mat3::Identity();
  Vec3 half = Vec3::Zero();

  /// Smallest world AABB containing the box.
  [[nodiscard]] Aabb bounds() const {
    const Vec3 r = axes.cwiseAbs() * half;
    return {center - r, center + r};
  }
};

/// True if the closed boxes `a` and `b` share a point (touching counts). `b` must not be empty.
/// A tolerance of 1e-12 m on near-parallel edge pairs keeps the cross-product axes from separating by round-off.
[[nodiscard]] inline bool overlaps(const OrientedBox& a, const Aabb& b) {
  const Vec3 bh = 0.5 * (b.max - b.min);
  const Vec3 t = a.center - b.center();  // in b's (world) frame
  const Mat3& r = a.axes;                // r(i, j) = e_i · a_j
  const Mat3 abs_r = r.cwiseAbs().array() + 1e-12;
  for (int i = 0; i < 3; ++i)  // b's face normals
    if (std::abs(t[i]) > bh[i] + abs_r.row(i).dot(a.half)) return false;
  for (int j = 0; j < 3; ++j)  // a's face normals
    if (std::abs(t.dot(r.col(j))) > abs_r.col(j).dot(bh) + a.half[j]) return false;
  for (int i = 0; i < 3; ++i) {  // e_i × a_j
    const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
    for (int j = 0; j < 3; ++j) {
      const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      const double rb = bh[i1] * abs_r(i2, j) + bh[i2] * abs_r(i1, j);
      const double ra = a.half[j1] * abs_r(i, j2) + a.half[j2] * abs_r(i, j1);
      if (std::abs(t[i2] * r(i1, j) - t[i1] * r(i2, j)) > ra + rb) return false;
    }
  }
  return true;
}

}  // namespace nbs::detail
