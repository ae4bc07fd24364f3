// SPDX-License-Identifier: BSD-3-Clause
// detail::SpatialHash against brute force over every stored point: ball queries (completeness, documented order:
// ascending cell_key, then insertion order), any_candidate and any_candidate_near_segment, with points on both sides
// of zero so that cells cross block borders at negative coordinates.
#include "nbs_catch.hpp"

#include <algorithm>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

#include "nbs/mesh/detail/spatial_hash.hpp"
#include "nbs_random.hpp"

using nbs::Vec3;

namespace {
/// Distance from x to the segment p ± h·dir (dir unit).
double segment_distance(const Vec3& x, const Vec3& p, const Vec3& dir, double h) {
  const double t = std::clamp((x - p).dot(dir), -h, h);
  return (x - p - t * dir).norm();
}
}  // namespace

TEST_CASE("spatial hash: ball and segment queries equal brute force, in the documented order", "[mesh][hash]") {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-0.03, 0.03);
  const double cell = 0.003;
  nbs::detail::SpatialHash grid(cell);
  std::vector<Vec3> pts;
  for (std::uint32_t i = 0; i < 4000; ++i) {
    pts.push_back(nbs_test::random_vec3(u, rng));
    grid.insert(pts.back(), i);
  }
  for (int q = 0; q < 300; ++q) {
    const Vec3 c = nbs_test::random_vec3(u, rng);
    const double r = 0.001 + 0.007 * (q % 8) / 7.0;
    // Ball: the ids within r, in (cell_key, insertion) order.
    std::vector<std::uint32_t> got;
    grid.for_each_candidate(c, r, [&](std::uint32_t id, const Vec3& p) {
      CHECK(p == pts[id]);
      if ((p - c).norm() <= r) got.push_back(id);
    });
    std::vector<std::pair<std::uint64_t, std::uint32_t>> want;
    for (std::uint32_t i = 0; i < pts.size(); ++i)
      if ((pts[i] - c).norm() <= r) want.emplace_back(grid.cell_key(pts[i]), i);
    std::sort(want.begin(), want.end());
    std::vector<std::uint32_t> want_ids;
    for (const auto& w : want) want_ids.push_back(w.second);
    REQUIRE(got == want_ids);
    // any_candidate with an exact-distance predicate: true iff some point lies within r (the cube covers the ball).
    const bool any_ball = grid.any_candidate(c, r, [&](std::uint32_t, const Vec3& p) { return (p - c).norm() < r; });
    CHECK(any_ball == std::any_of(pts.begin(), pts.end(), [&](const Vec3& p) { return (p - c).norm() < r; }));
    // Segment: true iff some point lies within r of c ± h·dir.
    const Vec3 dir = nbs_test::random_vec3(u, rng).normalized();
    const double h = 0.002 * (q % 4), rs = 0.0005 + 0.001 * (q % 3);
    const auto near = [&](const Vec3& p) { return segment_distance(p, c, dir, h) < rs; };
    const bool any_seg =
        grid.any_candidate_near_segment(c, dir, h, rs, [&](std::uint32_t, const Vec3& p) { return near(p); });
    CHECK(any_seg == std::any_of(pts.begin(), pts.end(), near));
  }
}
