// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Random planning rays around the synthetic sphere of synthetic_scan.hpp (origins and ends in and around the box).
#include <cstdint>
#include <random>
#include <vector>

#include "nbs/space/probabilistic_voxel_space.hpp"

namespace nbs::test {

inline std::vector<Ray> random_rays(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-0.25, 0.25);
  std::vector<Ray> rays(n);
  for (auto& r : rays) {
    r.origin = Vec3(u(rng), u(rng), 0.1 + u(rng));
    r.end = Vec3(0.3 * u(rng), 0.3 * u(rng), 0.08 + 0.3 * u(rng));
  }
  return rays;
}

}  // namespace nbs::test
