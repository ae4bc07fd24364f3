// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Conformance harness for nbs::ScanSimulator (include/nbs/driver/concepts.hpp). For each given path (chosen
// so that the object is in view) the checked contract is:
//  - the Scan passes Scan::validate, has points, and rays_cast ≥ points;
//  - the same (path, sensor, seed) gives the identical Scan; another seed moves the points (if σ > 0);
//  - every point lies within 6 σ(d) + `surface_tol_m` of the true surface (`surface_distance`), at a distance from
//    its origin inside the working range widened by the noise, and with the noise switched off within
//    `surface_tol_m` of it;
//  - the sensor's frames: a LaserStripeProfiler's profiles are `profile_poses(path)` and each point lies in its
//    profile's fan plane (s_x–s_z) within the fan; an AreaSensor's scan is one frame at path.start() with every
//    point inside the field of view.
#include "nbs_catch.hpp"

#include <cmath>
#include <functional>
#include <type_traits>
#include <vector>

#include "nbs/planner/simulation_loop.hpp"
#include "nbs/sensor/area_sensor.hpp"
#include "nbs/sensor/laser_stripe_profiler.hpp"

namespace nbs::conformance {

struct ScanCase {
  std::vector<LinearScanPath> paths;
  std::function<double(const Vec3&)> surface_distance;  ///< unsigned distance to the true surface, metres
  double surface_tol_m = 1e-6;                          ///< model tolerance (tessellation, float casts)
};

namespace detail {
inline bool same_scan(const Scan& a, const Scan& b) {
  if (a.profile_poses.size() != b.profile_poses.size()) return false;
  for (std::size_t k = 0; k < a.profile_poses.size(); ++k)
    if (a.profile_poses[k].matrix() != b.profile_poses[k].matrix()) return false;
  return a.points == b.points && a.profile_of_point == b.profile_of_point && a.rays_cast == b.rays_cast;
}
}  // namespace detail

template <class S, class Sensor>
void check_scan_simulator_conformance(const S& scanner, const Sensor& sensor, const ScanCase& c) {
  static_assert(ScanSimulator<S, Sensor>);
  Sensor quiet = sensor;
  quiet.noise = RangeNoise{};
  for (std::size_t k = 0; k < c.paths.size(); ++k) {
    INFO("path " << k);
    const LinearScanPath& path = c.paths[k];
    const Scan scan = scanner.scan(path, sensor, 17);
    REQUIRE_NOTHROW(scan.validate());
    REQUIRE(scan.size() > 0);
    CHECK(scan.rays_cast >= scan.size());
    CHECK(detail::same_scan(scanner.scan(path, sensor, 17), scan));
    if (!sensor.noise.is_zero()) CHECK(scanner.scan(path, sensor, 18).points != scan.points);

    if constexpr (std::is_same_v<Sensor, LaserStripeProfiler>) {
      const std::vector<Pose> expected = sensor.profile_poses(path);
      REQUIRE(scan.profile_poses.size() == expected.size());
      for (std::size_t i = 0; i < expected.size(); ++i) CHECK(scan.profile_poses[i].matrix() == expected[i].matrix());
    } else if constexpr (std::is_same_v<Sensor, AreaSensor>) {
      REQUIRE(scan.profile_poses.size() == 1);
      CHECK(scan.profile_poses[0].matrix() == path.start().pose().matrix());
    }
    std::size_t off_surface = 0, off_range = 0, off_view = 0;
    for (std::size_t i = 0; i < scan.size(); ++i) {
      const Pose& pose = scan.profile_poses[scan.profile_of_point[i]];
      const Vec3 local = pose.linear().transpose() * (scan.points[i] - pose.translation());
      const double d = local.norm();
      const double bound = 6.0 * sensor.noise.sigma_m(d) + c.surface_tol_m;
      off_surface += c.surface_distance(scan.points[i]) > bound ? 1 : 0;
      off_range += (d < sensor.range.min_m - bound || d > sensor.range.max_m + bound) ? 1 : 0;
      if constexpr (std::is_same_v<Sensor, LaserStripeProfiler>) {
        off_view += (std::abs(local.y()) > 1e-6 * d + 1e-9 ||
                     std::abs(std::atan2(local.x(), local.z())) > 0.5 * sensor.fan_angle_rad + 1e-6)
                        ? 1
                        : 0;
      } else if constexpr (std::is_same_v<Sensor, AreaSensor>) {
        off_view += (local.z() <= 0.0 ||
                     std::abs(local.x() / local.z()) > std::tan(0.5 * sensor.horizontal_fov_rad) + 1e-6 ||
                     std::abs(local.y() / local.z()) > std::tan(0.5 * sensor.vertical_fov_rad) + 1e-6)
                        ? 1
                        : 0;
      }
    }
    CHECK(off_surface == 0);
    CHECK(off_range == 0);
    CHECK(off_view == 0);
    const Scan exact = scanner.scan(path, quiet, 17);
    REQUIRE_NOTHROW(exact.validate());
    std::size_t off_exact = 0;
    for (const Vec3& p : exact.points) off_exact += c.surface_distance(p) > c.surface_tol_m ? 1 : 0;
    CHECK(off_exact == 0);
  }
}

}  // namespace nbs::conformance
