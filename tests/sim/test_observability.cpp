// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include <cmath>
#include <limits>

#include "nbs/sim/observability.hpp"
#include "test_meshes.hpp"

using namespace nbs;

TEST_CASE("fibonacci_sphere gives unit directions with zero mean", "[sim][observability]") {
  const auto d = fibonacci_sphere(500);
  REQUIRE(d.size() == 500);
  Vec3 sum = Vec3::Zero();
  for (const auto& v : d) {
    REQUIRE(std::abs(v.norm() - 1.0) < 1e-12);
    sum += v;
  }
  CHECK(sum.norm() / 500.0 < 0.01);
}

TEST_CASE("c_obs of a convex object on the pedestal is 1", "[sim][observability]") {
  const IndexedMesh cube = test::box_mesh({0, 0, 0}, {0.1, 0.1, 0.1});
  const BruteForceRayCaster caster(cube);
  const SurfaceSamples s = sample_surface(cube, 1500, 8);
  ObservabilitySettings set;
  set.directions = 100;
  const Observability o = observability(s, caster, set);
  CHECK(o.non_bottom == s.non_bottom_count());
  CHECK(o.observable_count == o.non_bottom);
  CHECK(o.c_obs() == 1.0);
  for (std::size_t i = 0; i < s.size(); ++i) REQUIRE(o.observable[i] == !s.bottom[i]);
}

TEST_CASE("c_obs of an object with a deep narrow well is below 1, exactly where geometry says", "[sim][observability]") {
  // Cube 100 mm with a 10 mm wide, 80 mm deep well. A wall sample at depth h can only be seen along directions whose
  // elevation α satisfies tan α ≥ h / w (to clear the rim) and α ≤ 70° (incidence cut-off): impossible for
  // h > w·tan 70° ≈ 27.5 mm. Outer faces and the top are convex-visible.
  const double s = 0.1, w = 0.01, depth = 0.08;
  const IndexedMesh m = test::cube_with_well(s, w, depth);
  const BruteForceRayCaster caster(m);
  const SurfaceSamples samples = sample_surface(m, 1500, 21);
  ObservabilitySettings set;
  set.directions = 3000;
  set.threads = 3;
  const Observability o = observability(samples, caster, set);
  const double a = 0.5 * (s - w), b = 0.5 * (s + w);
  const double h_max = w * std::tan(set.incidence_cutoff_rad);
  std::size_t deep = 0, shallow = 0, outer = 0;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (samples.bottom[i]) continue;
    const Vec3& p = samples.points[i];
    const bool in_well = p.x() >= a - 1e-12 && p.x() <= b + 1e-12 && p.y() >= a - 1e-12 && p.y() <= b + 1e-12 &&
                         p.z() < s - 1e-12;
    const bool wall = in_well && std::abs(samples.normals[i].z()) < 1e-9;
    const double h = s - p.z();
    if (wall && h > h_max + 1e-4) {
      ++deep;
      REQUIRE_FALSE(o.observable[i]);
    } else if (wall && h < 0.015) {
      ++shallow;
      REQUIRE(o.observable[i]);
    } else if (!in_well) {
      ++outer;
      REQUIRE(o.observable[i]);
    }
  }
  CHECK(deep > 10);
  CHECK(shallow > 5);
  CHECK(outer > 1000);
  CHECK(o.c_obs() < 1.0);
  CHECK(o.c_obs() > 0.9);
  // Independent of the thread count.
  set.threads = 1;
  CHECK(observability(samples, caster, set).observable == o.observable);
}

TEST_CASE("observability rejects invalid settings", "[sim][observability][errors]") {
  const IndexedMesh cube = test::box_mesh({0, 0, 0}, {0.1, 0.1, 0.1});
  const BruteForceRayCaster caster(cube);
  const SurfaceSamples s = sample_surface(cube, 10, 8);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  ObservabilitySettings bad;
  bad.min_range_m = 0.0;
  CHECK_THROWS_AS(observability(s, caster, bad), InvalidArgument);
  bad = {};
  bad.max_range_m = 0.1;  // < min range
  CHECK_THROWS_AS(observability(s, caster, bad), InvalidArgument);
  bad = {};
  bad.incidence_cutoff_rad = nan;
  CHECK_THROWS_AS(observability(s, caster, bad), InvalidArgument);
  bad = {};
  bad.directions = 0;
  CHECK_THROWS_AS(observability(s, caster, bad), InvalidArgument);
}
