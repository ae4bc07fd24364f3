// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include <cmath>
#include <limits>
#include <set>
#include <vector>

#include "nbs/space/ray_traversal.hpp"
#include "nbs/utility/evaluate_candidates.hpp"
#include "nbs/utility/ray_occluder.hpp"
#include "nbs/utility/thesis_terms.hpp"
#include "test_terms_fixtures.hpp"

using namespace nbs;

namespace {

// A scene space (1 cm voxels, [0, 0.1)³) with a wall of occupied voxels at x = 6 (x ∈ [0.06, 0.07)) over the rows
// z = 0 .. 4 (z < 0.05); the rows z ≥ 5 are free up to x = 9 (p = 0.4). Everything else is unknown.
nbs_test::LogOddsSpace wall_space() {
  auto space = nbs_test::make_space();
  std::vector<std::pair<int, int>> wall, open;
  for (int y = 0; y < 10; ++y)
    for (int z = 0; z < 10; ++z) (z < 5 ? wall : open).push_back({y, z});
  space.integrate(nbs_test::rows_scan(wall, 6));
  space.integrate(nbs_test::rows_scan(open, 9));
  return space;
}

Aabb target_box(double x0, double x1, double y0 = 0.0, double y1 = 0.0999) { return Aabb{Vec3(x0, y0, 0.0), Vec3(x1, y1, 0.0999)}; }
// A beam along +x (or −x) at height z through y = 0.055, from x0 to x1.
Ray beam(double x0, double x1, double z) { return Ray{Vec3(x0, 0.055, z), Vec3(x1, 0.055, z)}; }
double x_at(const Ray& r, double f) { return r.origin.x() + f * (r.end.x() - r.origin.x()); }

// Brute-force oracle of VolumetricEntropy's value: the entropy sum of the voxels the rays visit in the space's box
// (each key once, each ray stopping after its first occupied voxel).
double entropy_sum(const nbs_test::LogOddsSpace& space, const std::vector<Ray>& rays) {
  std::set<std::uint64_t> seen;
  double sum = 0.0;
  const KeyBox keys = space.bounds_keys();
  for (const Ray& r : rays)
    traverse_segment(space.grid(), r.origin, r.end, [&](const VoxelKey& k) {
      if (!keys.contains(k)) return true;
      if (seen.insert(k.pack()).second) sum += voxel_entropy(space.probability(k));
      return !space.occupied(k);
    });
  return sum;
}

}  // namespace

TEST_CASE("VoxelSpaceOccluder cuts a beam at the first occupied scene voxel before the target", "[utility][occluder]") {
  const auto scene = wall_space();
  REQUIRE(scene.occupied(VoxelKey{6, 5, 2}));
  REQUIRE(!scene.occupied(VoxelKey{6, 5, 7}));
  const VoxelSpaceOccluder<nbs_test::LogOddsSpace> occ(scene, target_box(0.08, 0.0999));
  // Through the wall: cut just before the wall voxel, within one voxel diagonal of its face.
  const Ray low = beam(-0.05, 0.2, 0.025);
  const double f = occ(low);
  CHECK(f < 1.0);
  CHECK(x_at(low, f) <= 0.06 + 1e-12);
  CHECK(x_at(low, f) >= 0.06 - 0.01 * std::sqrt(3.0));
  // Above the wall (free rows) and past the wall from the other side (it lies behind the target): not cut.
  CHECK(occ(beam(-0.05, 0.2, 0.075)) == 1.0);
  CHECK(occ(beam(0.2, 0.0, 0.025)) == 1.0);
  // The target's own voxels never occlude: a target holding the wall, or one whose margin reaches it.
  CHECK(VoxelSpaceOccluder<nbs_test::LogOddsSpace>(scene, target_box(0.05, 0.0999))(low) == 1.0);
  CHECK(VoxelSpaceOccluder<nbs_test::LogOddsSpace>(scene, target_box(0.075, 0.0999), 0.02)(low) == 1.0);
  // A target on the other side of the wall, seen from +x: cut before the wall's far face (x = 0.07).
  const VoxelSpaceOccluder<nbs_test::LogOddsSpace> back(scene, target_box(0.0, 0.04));
  const Ray from_right = beam(0.2, -0.05, 0.025);
  const double g = back(from_right);
  CHECK(g < 1.0);
  CHECK(x_at(from_right, g) >= 0.07 - 1e-12);
  CHECK(x_at(from_right, g) <= 0.07 + 0.01 * std::sqrt(3.0));
  // Beams that miss the target or start inside it: not cut (though they pass the wall).
  CHECK(VoxelSpaceOccluder<nbs_test::LogOddsSpace>(scene, target_box(0.08, 0.0999, 0.0, 0.03))(low) == 1.0);
  CHECK(occ(beam(0.09, -0.05, 0.025)) == 1.0);
}

TEST_CASE("VoxelSpaceOccluder: bad input throws", "[utility][occluder]") {
  const auto scene = wall_space();
  CHECK_THROWS_AS(VoxelSpaceOccluder<nbs_test::LogOddsSpace>(scene, Aabb{}), InvalidArgument);
  CHECK_THROWS_AS(VoxelSpaceOccluder<nbs_test::LogOddsSpace>(scene, target_box(0.08, 0.0999), -0.01), InvalidArgument);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_AS(VoxelSpaceOccluder<nbs_test::LogOddsSpace>(scene, target_box(nan, 0.0999)), InvalidArgument);
  const VoxelSpaceOccluder<nbs_test::LogOddsSpace> occ(scene, target_box(0.08, 0.0999));
  CHECK_THROWS_AS(occ(beam(nan, 0.2, 0.025)), InvalidArgument);
}

TEST_CASE("evaluation with an occluder scores the cut beams (brute-force oracle)", "[utility][occluder]") {
  const auto space = nbs_test::make_space();  // all unknown: entropy 1 per voxel
  LaserStripeProfiler lsp;
  lsp.points_per_profile = 9;
  lsp.fan_angle_rad = 0.4;
  lsp.range = {0.005, 0.3};
  lsp.profile_spacing_m = 0.01;
  const Viewpoint v = Viewpoint::look_at(Vec3(0.05, 0.05, -0.08), Vec3(0.05, 0.05, 0.5), Vec3::UnitX());
  const std::vector<LinearScanPath> cands{LinearScanPath(v, v.position() + Vec3(0.0, 0.03, 0.0))};
  std::vector<Ray> rays;
  append_candidate_rays(cands[0], lsp, {}, rays);
  // The beams run from z ≈ −0.075 to 0.22 and enter the space at z = 0 (≈ 25 % of their length). Cut the ones
  // leaning to −x or −y at 20 % (nothing of the space seen), the others at 50 % (the space seen up to z ≈ 0.07).
  const auto cut_at = [](const Ray& r) { return r.end.x() + r.end.y() < r.origin.x() + r.origin.y() ? 0.2 : 0.5; };
  std::vector<Ray> cut = rays;
  for (Ray& r : cut) r.end = r.origin + cut_at(r) * (r.end - r.origin);
  EvaluationSetting with = nbs_test::threads(2);
  with.occluder = cut_at;
  const auto res = evaluate_candidates(cands, lsp, space, VolumetricEntropy(), with);
  const auto free = evaluate_candidates(cands, lsp, space, VolumetricEntropy(), nbs_test::threads(1));
  REQUIRE(res.ok());
  CHECK(res.rays[0] == rays.size());
  CHECK(res.values[0] == Approx(entropy_sum(space, cut)).epsilon(1e-12));
  CHECK(free.values[0] == Approx(entropy_sum(space, rays)).epsilon(1e-12));
  CHECK(res.values[0] < free.values[0]);
  // Fully occluded (0) and not occluded (1) beams; a value outside [0, 1] is an error naming it.
  with.occluder = [](const Ray&) { return 0.0; };
  CHECK(evaluate_candidates(cands, lsp, space, VolumetricEntropy(), with).values[0] == 0.0);
  with.occluder = [](const Ray&) { return 1.0; };
  CHECK(evaluate_candidates(cands, lsp, space, VolumetricEntropy(), with).values[0] == free.values[0]);
  with.occluder = [](const Ray&) { return 1.5; };
  CHECK_THROWS_WITH(evaluate_candidates(cands, lsp, space, VolumetricEntropy(), with),
                    Catch::Contains("ray occluder returned 1.5"));
}
