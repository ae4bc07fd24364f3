// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Random planning rays around the synthetic sphere of synthetic_scan.hpp (origins and ends in and around the box).
#include <cstdint>
#include <random>
#include <vector>

#include "nbs/space/probabilistic_voxel_space.hpp"
#include "nbs_random.hpp"

namespace nbs::test {

inline std::vector<Ray> random_rays(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-0.25, 0.25);
  std::vector<Ray> rays(n);
  for (auto& r : rays) {
    r.origin = nbs_test::random_vec3(u, rng) + Vec3(0.0, 0.0, 0.1);
    r.end = 0.3 * nbs_test::random_vec3(u, rng) + Vec3(0.0, 0.0, 0.08);
  }
  return rays;
}

}  // namespace nbs::test
