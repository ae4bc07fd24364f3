// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Synthetic laser-stripe scans of an analytic sphere (tests and benchmarks of the voxel space).
// Coordinates are rounded to float so that OctoMap (float points) sees exactly the same beams.

#include <cmath>
#include <cstdint>
#include <random>

#include "nbs/core/scan.hpp"
#include "nbs/core/viewpoint.hpp"

namespace nbs::test {

struct SphereLspSetup {
  Vec3 center = Vec3(0, 0, 0.08);
  double radius_m = 0.06;
  int profiles = 60;
  int rays_per_profile = 200;
  double fan_rad = 0.6;            // full opening angle of the fan (sensor x–z plane)
  double path_length_m = 0.12;     // sensor moves along its y axis
  double noise_sigma_m = 0.0;      // Gaussian range noise
};

inline Vec3 to_float(const Vec3& v) {
  return Vec3(static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z()));
}

// One linear scan: sensor at `position` looking at the sphere centre, moving along its y axis.
inline Scan sphere_lsp_scan(const SphereLspSetup& s, const Vec3& position, std::uint64_t seed) {
  const Viewpoint vp = Viewpoint::look_at(position, s.center, std::abs((s.center - position).normalized().z()) > 0.99
                                                                  ? Vec3::UnitX()
                                                                  : Vec3::UnitZ());
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  Scan scan;
  for (int k = 0; k < s.profiles; ++k) {
    Pose p = vp.pose();
    const double t = s.profiles > 1 ? static_cast<double>(k) / (s.profiles - 1) - 0.5 : 0.0;
    p.translation() = to_float(vp.position() + t * s.path_length_m * vp.y_axis());
    scan.profile_poses.push_back(p);
    const Vec3 o = p.translation();
    for (int j = 0; j < s.rays_per_profile; ++j) {
      const double a = (s.rays_per_profile > 1 ? static_cast<double>(j) / (s.rays_per_profile - 1) - 0.5 : 0.0) *
                       s.fan_rad;
      const Vec3 d = (std::cos(a) * vp.view_direction() + std::sin(a) * vp.x_axis()).normalized();
      const Vec3 oc = o - s.center;
      const double b = oc.dot(d), c = oc.squaredNorm() - s.radius_m * s.radius_m;
      const double disc = b * b - c;
      ++scan.rays_cast;
      if (disc < 0) continue;
      double range = -b - std::sqrt(disc);
      if (range <= 0) continue;
      if (s.noise_sigma_m > 0) range += s.noise_sigma_m * noise(rng);
      scan.add_point(to_float(o + range * d), static_cast<std::uint32_t>(k));
    }
  }
  return scan;
}

// Viewpoint i of n on a ring of radius `distance` around the sphere (elevation 30°).
inline Vec3 ring_position(const SphereLspSetup& s, int i, int n, double distance_m) {
  const double az = 2.0 * 3.14159265358979323846 * i / n, el = 0.5;
  return s.center + distance_m * nbs::unit_from_angles(az, el);
}

}  // namespace nbs::test
