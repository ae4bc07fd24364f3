// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include <algorithm>
#include <limits>
#include <numeric>
#include <random>

#include "nbs/scene/euclidean_clusters.hpp"
#include "nbs_random.hpp"

using namespace nbs;
using namespace nbs::scene;

namespace {
/// Single linkage by brute force: union-find over every pair at distance ≤ tol, the same ordering rules.
std::vector<std::vector<std::size_t>> brute_force_clusters(const std::vector<Vec3>& p, const ClusterSettings& s) {
  std::vector<std::size_t> parent(p.size());
  std::iota(parent.begin(), parent.end(), 0);
  const auto find = [&](std::size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = i + 1; j < p.size(); ++j)
      if ((p[i] - p[j]).squaredNorm() <= s.tolerance_m * s.tolerance_m) parent[find(i)] = find(j);
  std::vector<std::vector<std::size_t>> by_root(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) by_root[find(i)].push_back(i);
  std::vector<std::vector<std::size_t>> out;
  for (auto& c : by_root)
    if (!c.empty() && c.size() >= s.min_size && c.size() <= s.max_size) out.push_back(c);
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.front() < b.front(); });
  return out;
}
}  // namespace

TEST_CASE("euclidean_clusters equals brute-force single linkage", "[scene][cluster]") {
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 0.3), blob(-0.02, 0.02);
    std::vector<Vec3> p;
    for (int i = 0; i < 600; ++i) p.push_back(nbs_test::random_vec3(u, rng));  // sparse background
    for (int b = 0; b < 5; ++b) {  // dense blobs
      const Vec3 c = nbs_test::random_vec3(u, rng);
      for (int i = 0; i < 150; ++i) p.push_back(c + nbs_test::random_vec3(blob, rng));
    }
    for (const ClusterSettings s : {ClusterSettings{0.02, 1, 1'000'000}, ClusterSettings{0.015, 20, 400},
                                    ClusterSettings{0.03, 5, 1'000'000}}) {
      CAPTURE(seed, s.tolerance_m, s.min_size, s.max_size);
      const auto got = euclidean_clusters(p, s);
      CHECK(got == brute_force_clusters(p, s));
    }
  }
}

TEST_CASE("euclidean_clusters: bad input", "[scene][cluster]") {
  CHECK(euclidean_clusters(std::vector<Vec3>{}, ClusterSettings{}).empty());
  CHECK_THROWS_WITH(euclidean_clusters(std::vector<Vec3>{Vec3::Zero()}, ClusterSettings{0.0, 1, 10}),
                    nbs_test::Contains("tolerance_m"));
  CHECK_THROWS_WITH(euclidean_clusters(std::vector<Vec3>{Vec3::Zero()}, ClusterSettings{0.01, 10, 5}),
                    nbs_test::Contains("max_size"));
  const std::vector<Vec3> p{Vec3::Zero(), Vec3(0, std::numeric_limits<double>::infinity(), 0)};
  CHECK_THROWS_WITH(euclidean_clusters(p, ClusterSettings{}), nbs_test::Contains("point 1"));
}
