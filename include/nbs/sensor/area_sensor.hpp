// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Area (range-image) sensor: RGB-D camera or stereo pair, one frame per viewpoint.

#include <cmath>
#include <cstddef>
#include <numbers>
#include <vector>

#include "nbs/core/viewpoint.hpp"
#include "nbs/sensor/range_noise.hpp"
#include "nbs/sensor/working_range.hpp"

namespace nbs {

/// A pinhole range-image sensor with `width_px` × `height_px` rays. Sensor frame: x right, y down, z forward.
/// The ray of pixel (u, v) passes through the pixel centre: in the image plane z = 1 it is at
/// x = tan(h/2)·(2(u+½)/w − 1), y = tan(v_fov/2)·(2(v+½)/h − 1), so the outer pixel *edges* span the full FOV.
/// Rays are ordered row-major (index v·w + u). Plain value type; call `validate()` (the scanner does).
struct AreaSensor {
  int width_px = 640;                  ///< ≥ 1
  int height_px = 480;                 ///< ≥ 1
  double horizontal_fov_rad = 1.0;     ///< in (0, π)
  double vertical_fov_rad = 0.8;       ///< in (0, π)
  WorkingRange range{0.5, 3.5};        ///< metres along each ray
  RangeNoise noise;                    ///< σ(d) along the ray

  /// Throws InvalidArgument naming the first invalid field and its value.
  void validate() const {
    detail::require(width_px >= 1, "AreaSensor.width_px must be >= 1, got ", width_px);
    detail::require(height_px >= 1, "AreaSensor.height_px must be >= 1, got ", height_px);
    detail::require(std::isfinite(horizontal_fov_rad) && horizontal_fov_rad > 0.0 &&
                        horizontal_fov_rad < std::numbers::pi,
                    "AreaSensor.horizontal_fov_rad must be in (0, pi), got ", horizontal_fov_rad);
    detail::require(std::isfinite(vertical_fov_rad) && vertical_fov_rad > 0.0 && vertical_fov_rad < std::numbers::pi,
                    "AreaSensor.vertical_fov_rad must be in (0, pi), got ", vertical_fov_rad);
    range.validate("AreaSensor");
  }

  [[nodiscard]] std::size_t ray_count() const {
    return static_cast<std::size_t>(width_px) * static_cast<std::size_t>(height_px);
  }

  /// Unit direction of the ray through pixel (u, v) in the sensor frame.
  [[nodiscard]] Vec3 ray_direction_sensor(int u, int v) const {
    const double x = std::tan(0.5 * horizontal_fov_rad) * (2.0 * (u + 0.5) / width_px - 1.0);
    const double y = std::tan(0.5 * vertical_fov_rad) * (2.0 * (v + 0.5) / height_px - 1.0);
    return Vec3(x, y, 1.0).normalized();
  }

  /// Unit ray directions (row-major) in the world frame for viewpoint `view`; the common origin is
  /// `view.position()`. Validates the sensor.
  [[nodiscard]] std::vector<Vec3> frame_directions(const Viewpoint& view) const {
    validate();
    std::vector<Vec3> dirs;
    dirs.reserve(ray_count());
    const Mat3 r = view.pose().linear();
    for (int v = 0; v < height_px; ++v)
      for (int u = 0; u < width_px; ++u) dirs.push_back(r * ray_direction_sensor(u, v));
    return dirs;
  }
};

}  // namespace nbs
