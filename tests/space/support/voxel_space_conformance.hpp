// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Conformance suite of the VoxelSpace concept (nbs/space/concepts.hpp), run on every model in the repository and on
// a user-written space: check_voxel_space_conformance<S>(). Oracles are analytic: a wall of points at x = 0.055 m
// seen from x = −0.2 m along +x, so the voxels in front of the wall are free, the wall's voxels occupied, the rest
// unknown, and a ray along +x visits exactly the keys from the box's first x key to the wall's key.

#include "nbs_catch.hpp"

#include <cmath>
#include <concepts>
#include <cstdint>
#include <limits>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/core/scan.hpp"
#include "nbs/space/concepts.hpp"

namespace nbs::test {

/// The unknown area of the suite: the 10³ voxels of l_v = 0.01 m at the origin corner (a closed box ending exactly at
/// 0.1 would also overlap the voxels with key 10).
inline Aabb conformance_box() { return {Vec3(0.0, 0.0, 0.0), Vec3(0.0999, 0.0999, 0.0999)}; }

/// One scan from (−0.2, y, z) along +x to a wall of points at x = 0.055 (the centre column of voxels with x key 5
/// at l_v = 0.01), y, z on the voxel centres 0.025 … 0.075.
inline Scan wall_scan() {
  Scan s;
  for (int j = 2; j <= 7; ++j)
    for (int k = 2; k <= 7; ++k) {
      Pose p = Pose::Identity();
      p.translation() = Vec3(-0.2, 0.01 * j + 0.005, 0.01 * k + 0.005);
      s.profile_poses.push_back(p);
      s.add_point(Vec3(0.055, p.translation().y(), p.translation().z()), static_cast<std::uint32_t>(s.profile_poses.size() - 1));
    }
  return s;
}

template <class S>
std::size_t observed_voxels(const S& s) {
  std::size_t n = 0;
  s.for_each([&](const VoxelKey&, const typename S::State&) { ++n; });
  return n;
}

template <class S>
void check_voxel_space_conformance() {
  static_assert(VoxelSpace<S>);
  const double l = 0.01;
  S space(l, conformance_box());
  // Geometry: voxel_bounds = the voxels of bounds_keys shrunk by 10⁻⁶ l_v, bounds_keys = the keys of bounds.
  CHECK(space.resolution_m() == l);
  CHECK(space.grid().resolution_m() == l);
  const KeyBox keys = space.bounds_keys();
  CHECK(keys.min == space.grid().key_box(space.bounds()).min);
  CHECK(keys.max == space.grid().key_box(space.bounds()).max);
  CHECK(keys.min == VoxelKey{0, 0, 0});
  CHECK(keys.max == VoxelKey{9, 9, 9});
  for (int a = 0; a < 3; ++a) {
    CHECK(std::abs(space.voxel_bounds().min[a] - keys.min[a] * l) <= 2e-6 * l);
    CHECK(std::abs(space.voxel_bounds().max[a] - (keys.max[a] + 1) * l) <= 2e-6 * l);
  }
  // Empty: every voxel unknown (p = 0.5, not observed, not occupied), nothing to visit.
  const VoxelKey wall{5, 5, 5}, front{2, 5, 5}, behind{8, 5, 5};
  for (const VoxelKey& k : {wall, front, behind}) {
    CHECK(space.probability(k) == 0.5);
    CHECK_FALSE(space.observed(k));
    CHECK_FALSE(space.occupied(k));
    CHECK(space.model().probability(space.state(k)) == 0.5);
  }
  CHECK(observed_voxels(space) == 0);
  // A ray through the empty space visits every voxel of its row and hits nothing.
  const Ray row{Vec3(-0.2, 0.055, 0.055), Vec3(0.3, 0.055, 0.055)};
  const auto r0 = space.cast_ray(row, [](const VoxelKey&, const typename S::State&) { return true; });
  CHECK_FALSE(r0.hit);
  CHECK(r0.voxels == 10);

  // Bad input changes nothing.
  Scan bad = wall_scan();
  bad.points[3].x() = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_AS(space.integrate(bad), InvalidArgument);
  CHECK(observed_voxels(space) == 0);
  CHECK_THROWS_AS(space.cast_ray(Ray{Vec3(0, 0, 0), Vec3(std::numeric_limits<double>::infinity(), 0, 0)},
                                 [](const VoxelKey&, const typename S::State&) { return true; }),
                  InvalidArgument);

  // One scan of the wall: the wall's voxels occupied, those in front free, those behind unknown.
  const IntegrationStats st = space.integrate(wall_scan());
  CHECK(st.points == 36);
  CHECK(observed_voxels(space) > 36);
  CHECK(space.occupied(wall));
  CHECK(space.probability(wall) > 0.5);
  CHECK(space.observed(front));
  CHECK(space.probability(front) < 0.5);
  CHECK_FALSE(space.occupied(front));
  CHECK_FALSE(space.observed(behind));
  CHECK(space.probability(behind) == 0.5);
  CHECK(space.probability(space.grid().center(wall)) == space.probability(wall));
  CHECK(space.probability(Vec3(5.0, 5.0, 5.0)) == 0.5);  // outside the box
  space.for_each([&](const VoxelKey& k, const typename S::State& s) {
    CHECK(keys.contains(k));
    CHECK(space.model().probability(s) == space.probability(k));
  });

  // Planning casts: the keys x = 0 … 5 of the row, in order, stopping at the wall (hit).
  std::vector<VoxelKey> visited;
  const auto r1 = space.cast_ray(row, [&](const VoxelKey& k, const typename S::State&) {
    visited.push_back(k);
    return true;
  });
  CHECK(r1.hit);
  CHECK(r1.hit_key == wall);
  REQUIRE(visited.size() == 6);
  for (int x = 0; x <= 5; ++x) CHECK(visited[static_cast<std::size_t>(x)] == (VoxelKey{x, 5, 5}));
  CHECK(r1.voxels == 6);
  // A visitor returning false stops the cast at once; a ray missing the box visits nothing.
  const auto r2 = space.cast_ray(row, [](const VoxelKey&, const typename S::State&) { return false; });
  CHECK(r2.voxels == 1);
  CHECK_FALSE(r2.hit);
  const auto r3 = space.cast_ray(Ray{Vec3(-0.2, 0.5, 0.5), Vec3(0.3, 0.5, 0.5)},
                                 [](const VoxelKey&, const typename S::State&) { return true; });
  CHECK(r3.voxels == 0);
  // Capability: batched casts equal single casts for any thread count.
  if constexpr (BatchRayCastingSpace<S>) {
    std::vector<Ray> rays;
    for (int j = 0; j < 10; ++j)
      for (int k = 0; k < 10; ++k)
        rays.push_back({Vec3(-0.2, 0.01 * j + 0.004, 0.01 * k + 0.006), Vec3(0.3, 0.01 * k + 0.002, 0.01 * j + 0.007)});
    for (unsigned threads : {1u, 3u}) {
      const auto batch = space.cast_rays(rays, threads, [](std::size_t, const VoxelKey&, const typename S::State&) {
        return true;
      });
      REQUIRE(batch.size() == rays.size());
      for (std::size_t i = 0; i < rays.size(); ++i) {
        const auto one = space.cast_ray(rays[i], [](const VoxelKey&, const typename S::State&) { return true; });
        CHECK(batch[i].hit == one.hit);
        CHECK(batch[i].voxels == one.voxels);
        CHECK(batch[i].hit_key == one.hit_key);
      }
    }
  }
  // Capability: integrate(scan, threads) gives the space integrate(scan) gives, for any thread count (a scan of 4,900
  // beams from 70 origins: four threads).
  if constexpr (ParallelIntegratingSpace<S>) {
    Scan dense;
    for (int j = 0; j < 70; ++j) {
      Pose p = Pose::Identity();
      p.translation() = Vec3(-0.2, 0.001 + 0.0014 * j, 0.05 + 0.3 * std::sin(j));
      dense.profile_poses.push_back(p);
      for (int k = 0; k < 70; ++k)
        dense.add_point(Vec3(0.03 + 0.0009 * k, 0.0013 * k + 0.0005, 0.0014 * j + 0.0003), static_cast<std::uint32_t>(j));
    }
    S one(l, conformance_box());
    const IntegrationStats a = one.integrate(dense);
    for (unsigned threads : {2u, 3u}) {
      S many(l, conformance_box());
      const IntegrationStats b = many.integrate(dense, threads);
      CHECK(a.integrated == b.integrated);
      CHECK(a.voxel_updates == b.voxel_updates);
      CHECK(a.voxels_same_scan == b.voxels_same_scan);
      CHECK(a.voxels_similar_beam == b.voxels_similar_beam);
      CHECK(observed_voxels(many) == observed_voxels(one));
      std::size_t differ = 0;
      one.for_each([&](const VoxelKey& k, const typename S::State& s) {
        differ += many.observed(k) && many.model().probability(many.state(k)) == one.model().probability(s) ? 0 : 1;
      });
      CHECK(differ == 0);
    }
    CHECK(a.voxel_updates > 300);  // of the 1,000 voxels
  }
}

}  // namespace nbs::test
