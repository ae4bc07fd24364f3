// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Seeded random scans into the box (−0.1, −0.1, 0) – (0.1, 0.1, 0.2) m (tests of the voxel space's update walks).

#include <cstdint>
#include <random>

#include "nbs/core/scan.hpp"
#include "nbs_random.hpp"

namespace nbs::test {

// `profiles` profiles, each from one origin at 0.2–0.4 m from the box centre, with `rays` beams to points spread over
// the box (a few outside it, counted as rejected), origins and end points on float values.
inline Scan random_scan(std::mt19937_64& rng, int profiles, int rays) {
  std::uniform_real_distribution<double> u(-1.0, 1.0), r(0.2, 0.4);
  Scan s;
  for (int p = 0; p < profiles; ++p) {
    Pose pose = Pose::Identity();
    const double radius = r(rng);
    pose.translation() = (Vec3(0.0, 0.0, 0.1) + radius * nbs_test::random_vec3(u, rng).normalized()).cast<float>().cast<double>();
    s.profile_poses.push_back(pose);
    const Vec3 aim = Vec3(0.0, 0.0, 0.1) + 0.09 * nbs_test::random_vec3(u, rng);
    for (int i = 0; i < rays; ++i)  // a cluster around `aim`, so beams revisit voxels within the scan
      s.add_point((aim + 0.02 * nbs_test::random_vec3(u, rng)).cast<float>().cast<double>(), static_cast<std::uint32_t>(p));
  }
  s.rays_cast = s.points.size();
  return s;
}

}  // namespace nbs::test
