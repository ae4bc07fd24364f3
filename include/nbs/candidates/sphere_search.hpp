// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Sphere search baseline (Sec. 4.7.2): fixed scan paths on a sphere around the object, inclination × azimuth.

#include <numbers>
#include <vector>

#include "nbs/core/scan_path.hpp"

namespace nbs {

/// Settings of the sphere search space. Defaults: 9 inclinations × 9 azimuths = 81 scan paths of 0.30 m
/// (Sec. 4.7.2). Inclination is measured from +z (world up); the thesis does not give the range. We use [10°, 90°]:
/// from nearly overhead down to horizontal, so no sensor position lies below the sphere centre.
struct SphereSearchSetting {
  int inclinations = 9;
  int azimuths = 9;
  double min_inclination_rad = 10.0 * std::numbers::pi / 180.0;
  double max_inclination_rad = 90.0 * std::numbers::pi / 180.0;
  double path_length_m = 0.30;

  void validate() const {
    detail::require(inclinations >= 1, "sphere search: inclinations must be >= 1, got ", inclinations);
    detail::require(azimuths >= 1, "sphere search: azimuths must be >= 1, got ", azimuths);
    detail::require_in_range("sphere search min_inclination_rad", min_inclination_rad, 0.0, std::numbers::pi);
    detail::require_in_range("sphere search max_inclination_rad", max_inclination_rad, min_inclination_rad,
                             std::numbers::pi);
    detail::require_non_negative("sphere search path_length_m", path_length_m);
  }
};

/// The sphere search space: for inclination θ_k (evenly from min to max) and azimuth φ_j = 2πj / azimuths, a
/// viewpoint on the sphere of radius `radius_m` around `center` looking at the centre (sensor x horizontal), and a
/// linear path of `path_length_m` along the sensor y axis (the meridian tangent) centred on that viewpoint.
/// Order: inclination-major. Throws InvalidArgument on non-finite centre or radius ≤ 0.
[[nodiscard]] inline std::vector<LinearScanPath> sphere_scan_paths(const Vec3& center, double radius_m,
                                                                   const SphereSearchSetting& s = {}) {
  validate_finite(center, "sphere search centre");
  detail::require_positive("sphere search radius_m", radius_m);
  s.validate();
  std::vector<LinearScanPath> paths;
  paths.reserve(static_cast<std::size_t>(s.inclinations * s.azimuths));
  for (int k = 0; k < s.inclinations; ++k) {
    const double t = s.inclinations == 1 ? 0.5 : double(k) / double(s.inclinations - 1);
    const double theta = s.min_inclination_rad + t * (s.max_inclination_rad - s.min_inclination_rad);
    for (int j = 0; j < s.azimuths; ++j) {
      const double phi = 2.0 * std::numbers::pi * j / s.azimuths;
      const Vec3 dir(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
      const Vec3 pos = center + radius_m * dir;
      // Horizontal sensor x even at the pole (θ = 0): use the azimuth's tangent as "up" reference there.
      const Vec3 up = std::sin(theta) > 1e-9 ? Vec3::UnitZ() : Vec3(-std::cos(phi), -std::sin(phi), 0.0);
      const Viewpoint mid = Viewpoint::look_at(pos, center, up);
      const Vec3 half = 0.5 * s.path_length_m * mid.y_axis();
      Pose start = mid.pose();
      start.translation() = pos - half;
      paths.emplace_back(Viewpoint(start), pos + half);
    }
  }
  return paths;
}

}  // namespace nbs
