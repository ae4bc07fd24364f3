// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The tests' small close-range depth camera: 128 × 96 px, 0.15–0.45 m, ≈ 1.5 mm pixels at d_s = 0.3 m, σ = 0.2 mm.
#include "nbs/sensor/area_sensor.hpp"

namespace nbs_test {

inline nbs::AreaSensor small_camera() {
  nbs::AreaSensor s;
  s.width_px = 128;
  s.height_px = 96;
  s.horizontal_fov_rad = 0.6;
  s.vertical_fov_rad = 0.45;
  s.range = {0.15, 0.45};
  s.noise = nbs::RangeNoise::constant(0.0002);
  return s;
}

}  // namespace nbs_test
