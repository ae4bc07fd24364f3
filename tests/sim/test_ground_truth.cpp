// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include <cmath>

#include "nbs/sim/metrics.hpp"
#include "test_meshes.hpp"

using namespace nbs;

TEST_CASE("GroundTruth composes samples, completeness, ē and c_obs", "[sim][ground_truth]") {
  const IndexedMesh cube = test::box_mesh({0, 0, 0}, {0.05, 0.05, 0.05});
  GroundTruth::Setting set;
  set.sample_density_per_m2 = 2.0e5;  // 0.015 m² · 2e5 = 3000 samples
  const GroundTruth gt(cube, set);
  CHECK(gt.samples().size() == static_cast<std::size_t>(std::ceil(cube.area() * set.sample_density_per_m2)));
  CHECK(gt.setting().completeness_radius_m == Parameters{}.completeness_radius_m);

  // A model of the top face only (2 mm grid); oracle: brute-force count of samples within r of a model point.
  std::vector<Vec3> model;
  for (int i = 0; i <= 25; ++i)
    for (int j = 0; j <= 25; ++j) model.emplace_back(0.002 * i, 0.002 * j, 0.05);
  const double r = gt.setting().completeness_radius_m;
  std::size_t oracle = 0;
  for (const Vec3& p : gt.samples().points) {
    bool hit = false;
    for (const Vec3& v : model) hit = hit || (v - p).squaredNorm() <= r * r;
    oracle += hit ? 1 : 0;
  }
  const Completeness c = gt.completeness(model);
  CHECK(c.covered == oracle);
  CHECK(c.covered > 500);  // at least the top face (a sixth of 3000 samples)
  CoverageTracker tracker = gt.tracker();
  tracker.add(model);
  CHECK(tracker.completeness().covered == c.covered);
  CHECK(gt.rms_error(model) < 1e-15);

  const BruteForceRayCaster caster(gt.mesh());
  ObservabilitySettings os;
  os.directions = 50;
  CHECK(gt.observability(caster, os).c_obs() == 1.0);
}

TEST_CASE("GroundTruth rejects bad input", "[sim][ground_truth][errors]") {
  CHECK_THROWS_AS(GroundTruth(IndexedMesh{}), InvalidArgument);
  GroundTruth::Setting set;
  set.completeness_radius_m = 0.0;
  CHECK_THROWS_AS(GroundTruth(test::box_mesh({0, 0, 0}, {1, 1, 1}), set), InvalidArgument);
  set = {};
  set.sample_density_per_m2 = -1.0;
  CHECK_THROWS_AS(GroundTruth(test::box_mesh({0, 0, 0}, {1, 1, 1}), set), InvalidArgument);
}
