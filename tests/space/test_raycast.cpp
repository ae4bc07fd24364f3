// SPDX-License-Identifier: BSD-3-Clause
// Planning ray casts: oracle = traverse_segment + first occupied voxel; parallel results equal serial ones.
#include "nbs_catch.hpp"

#include <random>
#include <stdexcept>
#include <vector>

#include "nbs/space/probabilistic_voxel_space.hpp"
#include "nbs/space/ray_traversal.hpp"
#include "support/random_rays.hpp"
#include "support/synthetic_scan.hpp"

namespace {
using nbs::Vec3;
using nbs::VoxelKey;

nbs::ProbabilisticVoxelSpace<> modelled_sphere(const nbs::test::SphereLspSetup& setup) {
  nbs::ProbabilisticVoxelSpace<> space(0.004, nbs::Aabb{Vec3(-0.1, -0.1, 0.0), Vec3(0.1, 0.1, 0.2)});
  for (int i = 0; i < 6; ++i)
    (void)space.integrate(nbs::test::sphere_lsp_scan(setup, nbs::test::ring_position(setup, i, 6, 0.3), i));
  return space;
}

using nbs::test::random_rays;
}  // namespace

TEST_CASE("cast_ray stops at the first occupied voxel along the DDA path", "[space][raycast]") {
  const nbs::test::SphereLspSetup setup{.profiles = 30, .rays_per_profile = 80};
  const auto space = modelled_sphere(setup);
  int hits = 0;
  for (const auto& ray : random_rays(300, 5)) {
    std::vector<VoxelKey> seen;
    const auto r = space.cast_ray(ray, [&](const VoxelKey& k, const nbs::ThesisState& s) {
      REQUIRE(s == space.state(k));
      seen.push_back(k);
    });
    REQUIRE(r.voxels == seen.size());
    // Oracle: the clipped segment's voxels up to and including the first occupied one.
    std::vector<VoxelKey> expected;
    double t0, t1;
    if (nbs::detail::clip_segment(ray.origin, ray.end, space.voxel_bounds(), t0, t1)) {
      const Vec3 a = nbs::detail::point_in_box(ray.origin, ray.end, t0, space.voxel_bounds());
      const Vec3 b = nbs::detail::point_in_box(ray.origin, ray.end, t1, space.voxel_bounds());
      nbs::traverse_segment(space.grid(), a, b, [&](const VoxelKey& k) {
        expected.push_back(k);
        return !space.occupied(k);
      });
    }
    REQUIRE(seen == expected);
    REQUIRE(r.hit == (!expected.empty() && space.occupied(expected.back())));
    if (r.hit) {
      REQUIRE(r.hit_key == expected.back());
      ++hits;
    }
  }
  REQUIRE(hits > 20);
  REQUIRE(hits < 300);
}

TEST_CASE("cast_rays gives identical results for any thread count", "[space][raycast]") {
  const nbs::test::SphereLspSetup setup{.profiles = 30, .rays_per_profile = 80};
  const auto space = modelled_sphere(setup);
  const auto rays = random_rays(2000, 77);
  const auto run = [&](unsigned threads) {
    std::vector<double> unknown(rays.size(), 0.0);  // a utility term: summed entropy proxy per ray
    auto res = space.cast_rays(rays, threads, [&](std::size_t i, const VoxelKey&, const nbs::ThesisState& s) {
      if (s == nbs::ThesisState{}) unknown[i] += 1.0;
    });
    return std::pair(res, unknown);
  };
  const auto [r1, u1] = run(1);
  for (unsigned t : {2u, 3u, 7u}) {
    const auto [rt, ut] = run(t);
    REQUIRE(ut == u1);
    for (std::size_t i = 0; i < rays.size(); ++i) {
      REQUIRE(rt[i].hit == r1[i].hit);
      REQUIRE(rt[i].voxels == r1[i].voxels);
      REQUIRE(rt[i].hit_key == r1[i].hit_key);
    }
  }
  // An exception thrown by the callback reaches the caller after every thread has stopped.
  for (unsigned t : {1u, 3u})
    REQUIRE_THROWS_AS(space.cast_rays(rays, t,
                                      [&](std::size_t i, const VoxelKey&, const nbs::ThesisState&) {
                                        if (i == 1500) throw std::runtime_error("visit failed");
                                      }),
                      std::runtime_error);
}

TEST_CASE("cast_ray: rays missing the unknown area and bad rays", "[space][raycast]") {
  nbs::ProbabilisticVoxelSpace<> space(0.01, nbs::Aabb{Vec3::Zero(), Vec3::Constant(0.1)});
  const auto r = space.cast_ray({Vec3(1, 1, 1), Vec3(2, 1, 1)}, [](const VoxelKey&, const nbs::ThesisState&) {});
  REQUIRE(r.voxels == 0);
  REQUIRE_FALSE(r.hit);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<nbs::Ray> rays{{Vec3::Zero(), Vec3::Ones()}, {Vec3(nan, 0, 0), Vec3::Ones()}};
  int calls = 0;
  REQUIRE_THROWS_AS(space.cast_rays(rays, 2, [&](std::size_t, const VoxelKey&, const nbs::ThesisState&) { ++calls; }),
                    nbs::InvalidArgument);
  REQUIRE(calls == 0);
  // Stopping early through the callback.
  const auto s = space.cast_ray({Vec3(-1, 0.05, 0.05), Vec3(1, 0.05, 0.05)},
                                [](const VoxelKey& k, const nbs::ThesisState&) { return k.x < 3; });
  REQUIRE(s.voxels == 4);
  REQUIRE_FALSE(s.hit);
}
