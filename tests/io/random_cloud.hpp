// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A seeded random point cloud for the reader/writer round trips.
#include <cstdint>
#include <random>

#include "nbs/io/point_cloud.hpp"
#include "nbs_random.hpp"

namespace nbs_test {

/// `n` points in [-2, 2]^3, optionally unit normals and random colours; the same seed gives the same cloud.
inline nbs::PointCloud random_cloud(std::size_t n, bool normals, bool colors, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  nbs::PointCloud c;
  for (std::size_t i = 0; i < n; ++i) {
    c.points.push_back(nbs_test::random_vec3(u, rng));
    if (normals) c.normals.push_back(nbs_test::random_vec3(u, rng).normalized());
    if (colors) c.colors.push_back({static_cast<std::uint8_t>(rng()), static_cast<std::uint8_t>(rng()),
                                    static_cast<std::uint8_t>(rng())});
  }
  return c;
}

}  // namespace nbs_test
