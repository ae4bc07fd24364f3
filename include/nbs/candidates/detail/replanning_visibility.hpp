// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Geometric part of the occlusion test of Alg. 3 (Sec. 4.5.2): can the sensor at one pose measure a target point
/// (field of view, working range, incidence), before the ray cast in the voxel space decides about occlusion.

#include <cmath>

#include "nbs/candidates/planning_context.hpp"
#include "nbs/candidates/scan_candidate.hpp"

namespace nbs::detail {

/// True if `target` lies in the sensor's view at pose T_WS: in front (z_S > 0), distance in the working range,
/// inside the FOV (line sensor: |atan2(x_S, z_S)| ≤ fov_x/2 and |y_S| ≤ fan_tolerance_m, the half spacing of the
/// sampled positions; area sensor: the pyramid of fov_x × fov_y), and incidence — the angle between the target
/// normal and the direction to the sensor — ≤ incidence_cutoff_rad (not checked for a zero normal).
[[nodiscard]] inline bool in_view(const Pose& T_WS, const SurfaceTarget& target, const SensorGeometry& sensor,
                                  double fan_tolerance_m, double incidence_cutoff_rad) {
  const Vec3 to_target = target.point - T_WS.translation();
  const Vec3 q = T_WS.linear().transpose() * to_target;  // target in S
  if (!(q.z() > 0.0)) return false;
  const double d = to_target.norm();
  if (!sensor.range.contains(d)) return false;
  if (std::abs(std::atan2(q.x(), q.z())) > 0.5 * sensor.fov_x_rad) return false;
  if (sensor.kind == SensorGeometry::Kind::line) {
    if (std::abs(q.y()) > fan_tolerance_m) return false;
  } else if (std::abs(std::atan2(q.y(), q.z())) > 0.5 * sensor.fov_y_rad) {
    return false;
  }
  const double n = target.normal.norm();
  if (n > 0.0) {
    const double cos_inc = -to_target.dot(target.normal) / (d * n);
    if (cos_inc < std::cos(incidence_cutoff_rad)) return false;
  }
  return true;
}

}  // namespace nbs::detail
