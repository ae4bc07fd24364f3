// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Laser stripe profiler: a fan of rays in the sensor x–z plane, swept along a linear scan path (Sec. 4.3.2).

#include <cmath>
#include <cstddef>
#include <numbers>
#include <vector>

#include "nbs/core/scan_path.hpp"
#include "nbs/sensor/range_noise.hpp"
#include "nbs/sensor/working_range.hpp"

namespace nbs {

/// A laser stripe profiler (LSP). One profile is a fan of `points_per_profile` rays in the sensor x–z plane,
/// symmetric about +z (the viewing direction), spanning `fan_angle_rad`; ray i makes the angle
/// θ_i = −fan/2 + i · fan/(n−1) with +z, towards +x for θ > 0 (a single ray points along +z).
/// Along a linear scan path one profile is taken every ≤ `profile_spacing_m` (see `profile_poses`).
/// Plain value type; call `validate()` (the scanner does).
struct LaserStripeProfiler {
  int points_per_profile = 640;        ///< rays per profile, ≥ 1
  double fan_angle_rad = 0.5;          ///< full opening angle of the fan, in (0, π)
  WorkingRange range{0.15, 0.45};      ///< metres along each ray
  double profile_spacing_m = 0.001;    ///< maximal distance between consecutive profiles along a path, > 0
  RangeNoise noise;                    ///< σ(d) along the ray

  /// Throws InvalidArgument naming the first invalid field and its value.
  void validate() const {
    detail::require(points_per_profile >= 1, "LaserStripeProfiler.points_per_profile must be >= 1, got ",
                    points_per_profile);
    detail::require(std::isfinite(fan_angle_rad) && fan_angle_rad > 0.0 && fan_angle_rad < std::numbers::pi,
                    "LaserStripeProfiler.fan_angle_rad must be in (0, pi), got ", fan_angle_rad);
    range.validate("LaserStripeProfiler");
    detail::require_positive("LaserStripeProfiler.profile_spacing_m", profile_spacing_m);
  }

  /// Angle θ_i of ray i with the sensor z axis (radians, positive towards +x).
  [[nodiscard]] double ray_angle_rad(int i) const {
    if (points_per_profile == 1) return 0.0;
    return -0.5 * fan_angle_rad + fan_angle_rad * static_cast<double>(i) / (points_per_profile - 1);
  }

  /// Unit direction of ray i in the sensor frame: (sin θ_i, 0, cos θ_i).
  [[nodiscard]] Vec3 ray_direction_sensor(int i) const {
    const double t = ray_angle_rad(i);
    return {std::sin(t), 0.0, std::cos(t)};
  }

  /// Unit directions of the profile's rays in the world frame for sensor pose T_WS; the common origin is
  /// `pose.translation()`. Validates the sensor and the pose.
  [[nodiscard]] std::vector<Vec3> profile_directions(const Pose& pose) const {
    validate();
    validate_pose(pose, "profile pose");
    std::vector<Vec3> dirs(static_cast<std::size_t>(points_per_profile));
    const Mat3 r = pose.linear();
    for (int i = 0; i < points_per_profile; ++i) dirs[static_cast<std::size_t>(i)] = r * ray_direction_sensor(i);
    return dirs;
  }

  /// Number of profiles along a path of length L: ⌈L / spacing⌉ + 1 (1 for L = 0), so that the first and the
  /// last pose are both included and consecutive profiles are ≤ `profile_spacing_m` apart.
  [[nodiscard]] std::size_t profile_count(double path_length_m) const {
    validate();
    detail::require_non_negative("path length", path_length_m);
    // The small slack keeps a length that is an exact multiple of the spacing (up to rounding) at L/s + 1.
    return static_cast<std::size_t>(std::ceil(path_length_m / profile_spacing_m - 1e-9)) + 1;
  }

  /// Sensor poses T_WS of the profiles along `path`, evenly spaced from its start to its end (both included),
  /// `profile_count(path.length())` of them. The path is meant to move along the sensor's y axis (Sec. 4.3.2)
  /// but any direction is accepted.
  [[nodiscard]] std::vector<Pose> profile_poses(const LinearScanPath& path) const {
    const std::size_t n = profile_count(path.length());
    std::vector<Pose> poses;
    poses.reserve(n);
    for (std::size_t k = 0; k < n; ++k)
      poses.push_back(path.pose_at(n == 1 ? 0.0 : static_cast<double>(k) / static_cast<double>(n - 1)));
    return poses;
  }
};

}  // namespace nbs
