// SPDX-License-Identifier: BSD-3-Clause
// enclosed_by_surface (the enclosure test of the unseen_open ĉ_m) against analytic cases: a closed cubic shell of
// occupied voxels encloses its centre; an opening on top or at a side frees it; an opening in the floor does not
// (the test looks up and sideways only: below is the support); a point outside is free. With LowViews a lid without
// a floor (an overhang) frees a point under it that a sensor above the support could see, not one on the support.
#include "nbs_catch.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <numbers>

#include "nbs/candidates/enclosure.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"

using nbs::Vec3;

namespace {

using Space = nbs::ProbabilisticVoxelSpace<>;
constexpr double kVoxel = 0.005;
constexpr int kHalf = 4;  // the shell: voxel indices with max(|i|, |j|, |k|) == kHalf (voxel centres (i + 0.5) l_v)

enum class Opening { none, top, side, floor, no_floor };

/// True if the shell voxel (i, j, k) is left out by `o`: the 3×3 voxels in the middle of the top (+z), a side (+x)
/// or the floor (−z) face, or the whole floor layer (a lid: top and sides only).
bool left_out(int i, int j, int k, Opening o) {
  const auto mid = [](int a, int b) { return std::abs(a) <= 1 && std::abs(b) <= 1; };
  switch (o) {
    case Opening::top: return k == kHalf && mid(i, j);
    case Opening::side: return i == kHalf && mid(j, k);
    case Opening::floor: return k == -kHalf && mid(i, j);
    case Opening::no_floor: return k == -kHalf;
    case Opening::none: break;
  }
  return false;
}

/// One end point per shell voxel (its centre), each measured by a beam from 0.1 m outside along the face normal, so
/// the shell's inside stays unknown.
Space shell_space(Opening o) {
  Space space(kVoxel, nbs::Aabb{Vec3::Constant(-0.1), Vec3::Constant(0.1)});
  nbs::Scan scan;
  for (int i = -kHalf; i <= kHalf; ++i)
    for (int j = -kHalf; j <= kHalf; ++j)
      for (int k = -kHalf; k <= kHalf; ++k) {
        if (std::max({std::abs(i), std::abs(j), std::abs(k)}) != kHalf || left_out(i, j, k, o)) continue;
        const Vec3 p = (Vec3(i, j, k) + Vec3::Constant(0.5)) * kVoxel;
        // The outward normal of the voxel's face (x first, then y, then z at edges and corners).
        const Vec3 out = std::abs(i) == kHalf   ? Vec3(i, 0, 0)
                         : std::abs(j) == kHalf ? Vec3(0, j, 0)
                                                : Vec3(0, 0, k);
        nbs::Pose pose = nbs::Pose::Identity();
        pose.translation() = p + 0.1 * out.normalized();
        scan.profile_poses.push_back(pose);
        scan.add_point(p, static_cast<std::uint32_t>(scan.profile_poses.size() - 1));
      }
  (void)space.integrate(scan);
  return space;
}

}  // namespace

TEST_CASE("enclosure: the 17 directions are unit, point up or sideways and are distinct", "[enclosure]") {
  const auto& dirs = nbs::detail::upper_directions();
  for (std::size_t a = 0; a < dirs.size(); ++a) {
    CHECK(std::abs(dirs[a].norm() - 1.0) < 1e-12);
    CHECK(dirs[a].z() >= 0.0);
    for (std::size_t b = 0; b < a; ++b) CHECK((dirs[a] - dirs[b]).norm() > 0.1);
  }
}

TEST_CASE("enclosure: a closed shell encloses its centre; openings on top or at a side free it, the floor not",
          "[enclosure]") {
  const Vec3 centre = Vec3::Constant(0.5 * kVoxel);  // the middle voxel of the shell
  const double reach = 0.35;
  const Space closed = shell_space(Opening::none);
  // The shell is measured surface, its inside unknown (the test relies on both).
  REQUIRE(closed.occupied(*closed.grid().key_of(Vec3((kHalf + 0.5) * kVoxel, centre.y(), centre.z()))));
  REQUIRE(std::abs(closed.probability(centre) - 0.5) < 1e-9);
  CHECK(nbs::enclosed_by_surface(closed, centre, reach));
  // Off-centre inside points are enclosed as well.
  CHECK(nbs::enclosed_by_surface(closed, Vec3(-0.012, 0.01, -0.014), reach));
  // Outside the shell: the rays away from it are free.
  CHECK_FALSE(nbs::enclosed_by_surface(closed, Vec3(0.04, 0.0, 0.0), reach));
  CHECK_FALSE(nbs::enclosed_by_surface(closed, Vec3(0.0, 0.0, 0.04), reach));
  // A short reach that ends inside the shell never meets it: nothing blocks those rays.
  CHECK_FALSE(nbs::enclosed_by_surface(closed, centre, 0.5 * kVoxel));

  CHECK_FALSE(nbs::enclosed_by_surface(shell_space(Opening::top), centre, reach));   // the +z ray leaves
  CHECK_FALSE(nbs::enclosed_by_surface(shell_space(Opening::side), centre, reach));  // the +x ray leaves
  CHECK(nbs::enclosed_by_surface(shell_space(Opening::floor), centre, reach));       // −z is not looked at
}

TEST_CASE("enclosure: the 33 lower directions are unit, point down, shallow first, and are distinct", "[enclosure]") {
  const auto& dirs = nbs::detail::lower_directions();
  for (std::size_t a = 0; a < dirs.size(); ++a) {
    CHECK(std::abs(dirs[a].norm() - 1.0) < 1e-12);
    CHECK(dirs[a].z() < 0.0);
    if (a > 0) CHECK(dirs[a].z() <= dirs[a - 1].z() + 1e-12);
    for (std::size_t b = 0; b < a; ++b) CHECK((dirs[a] - dirs[b]).norm() > 0.05);
  }
  CHECK(dirs.front().z() == Approx(-std::sin(5.0 * std::numbers::pi / 180.0)));
  CHECK(dirs.back() == Vec3(0, 0, -1));
}

TEST_CASE("enclosure: looking down frees a point under a lid high above the support, not one on the support",
          "[enclosure]") {
  const double reach = 0.35;
  const Space lid = shell_space(Opening::no_floor);
  // A point low inside the lid (under its top, between its sides, above the missing floor): its upward and
  // horizontal rays all meet the lid, so the upper test calls it walled in.
  const Vec3 x(0.5 * kVoxel, 0.5 * kVoxel, -0.012);
  REQUIRE(nbs::enclosed_by_surface(lid, x, reach));
  // The support 0.2 m below: a sensor 0.15 m away stands above it along every lower direction. The −10° rays pass
  // under the sides (17.5 mm away they are 3.1 mm lower, at z = −15.1 mm, below the lowest side voxel's −15 mm) and
  // straight down leaves through the missing floor: not enclosed.
  CHECK_FALSE(nbs::enclosed_by_surface(lid, x, reach, nbs::LowViews{x.z() - 0.2, 0.15}));
  // The support 20 mm below: only the −5° ring is admissible (a sensor 0.15 m away drops 13.1 mm; −10° would drop
  // 26.0 mm, into the support), and its rays meet the sides 1.5 mm lower: enclosed.
  CHECK(nbs::enclosed_by_surface(lid, x, reach, nbs::LowViews{x.z() - 0.02, 0.15}));
  // On the support (5 mm above it: even −5° would put the sensor 13 mm lower, into the support): the upper test's
  // answer.
  CHECK(nbs::enclosed_by_surface(lid, x, reach, nbs::LowViews{x.z() - 0.005, 0.15}));
  // The closed shell encloses its centre from below too; a point outside stays free.
  const Space closed = shell_space(Opening::none);
  CHECK(nbs::enclosed_by_surface(closed, Vec3::Constant(0.5 * kVoxel), reach, nbs::LowViews{-0.2, 0.15}));
  CHECK_FALSE(nbs::enclosed_by_surface(closed, Vec3(0.0, 0.0, 0.04), reach, nbs::LowViews{-0.2, 0.15}));
  // The floor's 3×3 opening: straight down leaves through it once a sensor 0.15 m below the centre stands above
  // the support.
  const Space floor = shell_space(Opening::floor);
  const Vec3 c = Vec3::Constant(0.5 * kVoxel);
  CHECK_FALSE(nbs::enclosed_by_surface(floor, c, reach, nbs::LowViews{c.z() - 0.2, 0.15}));
  CHECK(nbs::enclosed_by_surface(floor, c, reach, nbs::LowViews{c.z() - 0.1, 0.15}));
  // surface_seen with and without LowViews.
  CHECK(nbs::surface_seen(lid, 0.6, reach, true)(x));
  CHECK_FALSE(nbs::surface_seen(lid, 0.6, reach, true, nbs::LowViews{x.z() - 0.2, 0.15})(x));
  CHECK_FALSE(nbs::surface_seen(lid, 0.6, reach, false)(x));
}
