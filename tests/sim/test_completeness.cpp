// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include <cmath>
#include <limits>
#include <random>

#include "nbs/sim/completeness.hpp"
#include "nbs/sim/observability.hpp"
#include "test_meshes.hpp"
#include "nbs_random.hpp"

using namespace nbs;

namespace {

const Vec3 kCentre(0, 0, 0.5);  // floating: no bottom samples
constexpr double kRadius = 0.05;

// Dense model vertices on the analytic upper hemisphere (z ≥ centre z), ≈ 0.5 mm spacing.
std::vector<Vec3> upper_hemisphere_points() {
  std::vector<Vec3> pts;
  for (const Vec3& d : fibonacci_sphere(120000))
    if (d.z() >= 0.0) pts.push_back(kCentre + kRadius * d);
  return pts;
}

// Brute-force oracle: covered iff some model vertex v has (v − s)² ≤ r².
std::size_t brute_force_covered(const SurfaceSamples& s, const std::vector<Vec3>& model, double r) {
  std::size_t n = 0;
  for (const Vec3& p : s.points) {
    bool hit = false;
    for (const Vec3& v : model) hit = hit || (v - p).squaredNorm() <= r * r;
    n += hit ? 1 : 0;
  }
  return n;
}

}  // namespace

TEST_CASE("half a sphere observed gives c_a ≈ 0.5 plus the r-band below the equator", "[sim][completeness]") {
  const IndexedMesh sphere = test::uv_sphere(kCentre, kRadius, 96, 192);
  const SurfaceSamples s = sample_surface(sphere, 20000, 42);
  REQUIRE(s.non_bottom_count() == s.size());
  const double r = 0.003;
  const Completeness c = completeness(s, upper_hemisphere_points(), r);
  // Analytic: a sample at angle φ below the equator is within r of the equator iff 2R sin(φ/2) ≤ r; the band
  // 0 ≤ φ ≤ φ_r holds the area share sin(φ_r)/2.
  const double phi_r = 2.0 * std::asin(r / (2.0 * kRadius));
  const double expected = 0.5 + 0.5 * std::sin(phi_r);
  const double sd = std::sqrt(expected * (1 - expected) / 20000.0);
  CHECK(std::abs(c.c_a() - expected) < 5 * sd + 0.002);
  CHECK(c.c_b() == c.c_a());
}

TEST_CASE("completeness equals the brute-force count, and the incremental tracker agrees", "[sim][completeness]") {
  const IndexedMesh cube = test::box_mesh({0, 0, 0}, {0.1, 0.1, 0.1});
  const SurfaceSamples s = sample_surface(cube, 1500, 9);
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(-0.01, 0.11);
  std::vector<Vec3> model(600);
  for (auto& v : model) v = nbs_test::random_vec3(u, rng);
  const double r = 0.006;
  const Completeness one_shot = completeness(s, model, r, 1);
  CHECK(one_shot.covered == brute_force_covered(s, model, r));
  CHECK(one_shot.covered > 0);
  CHECK(one_shot.covered < s.size());
  CHECK(completeness(s, model, r, 3).covered == one_shot.covered);  // thread count does not matter

  CoverageTracker tracker(s, r);
  tracker.add(std::span<const Vec3>(model).first(250));
  const Completeness partial = tracker.completeness();
  tracker.add(std::span<const Vec3>(model).subspan(250));
  const Completeness full = tracker.completeness();
  CHECK(partial.covered <= full.covered);
  CHECK(full.covered == one_shot.covered);
  CHECK(full.covered_non_bottom == one_shot.covered_non_bottom);
  CHECK(full.non_bottom == s.non_bottom_count());
  CHECK(full.c_a() == one_shot.c_a());
  CHECK(full.c_b() == one_shot.c_b());
}

TEST_CASE("CoverageTracker: vertex-driven and sample-driven adds both give the brute-force flags", "[sim][completeness]") {
  const IndexedMesh cube = test::box_mesh({0, 0, 0}, {0.1, 0.1, 0.1});
  const SurfaceSamples s = sample_surface(cube, 4000, 5);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-0.01, 0.11);
  const double r = 0.008;
  CoverageTracker tracker(s, r);
  std::vector<Vec3> model;
  // Batches of 1 vertex (4000 uncovered >= 8 per vertex: vertex-driven) first, then growing batches until the
  // uncovered samples are fewer than 8 per new vertex (sample-driven); the flags are checked after every add.
  int vertex_driven = 0, sample_driven = 0;
  for (const std::size_t batch : {1, 1, 1, 5, 20, 50, 200, 400, 800, 1600}) {
    std::size_t uncovered = 0;
    for (bool c : tracker.covered()) uncovered += c ? 0 : 1;
    (uncovered < CoverageTracker::kSampleDrivenRatio * batch ? sample_driven : vertex_driven) += 1;
    std::vector<Vec3> fresh(batch);
    for (auto& v : fresh) v = nbs_test::random_vec3(u, rng);
    tracker.add(fresh);
    model.insert(model.end(), fresh.begin(), fresh.end());
    for (std::size_t i = 0; i < s.size(); ++i) {
      bool hit = false;
      for (const Vec3& v : model) hit = hit || (v - s.points[i]).squaredNorm() <= r * r;
      REQUIRE(tracker.covered()[i] == hit);
    }
  }
  CHECK(vertex_driven >= 3);
  CHECK(sample_driven >= 2);
  CHECK(tracker.completeness().covered == brute_force_covered(s, model, r));
}

TEST_CASE("c_a excludes the bottom, c_b includes it", "[sim][completeness]") {
  const IndexedMesh cube = test::box_mesh({0, 0, 0}, {0.1, 0.1, 0.1});
  const SurfaceSamples s = sample_surface(cube, 3000, 2);
  // The model is the ground-truth samples themselves minus the bottom: c_a = 1, c_b = non-bottom share.
  std::vector<Vec3> model;
  for (std::size_t i = 0; i < s.size(); ++i)
    if (!s.bottom[i]) model.push_back(s.points[i]);
  const Completeness c = completeness(s, model, 1e-9);
  CHECK(c.c_a() == 1.0);
  CHECK(c.c_b() == Approx(double(s.non_bottom_count()) / double(s.size())));
  CHECK(completeness(s, {}, 0.003).c_a() == 0.0);
}

TEST_CASE("completeness rejects bad radius and non-finite vertices", "[sim][completeness][errors]") {
  const SurfaceSamples s = sample_surface(test::box_mesh({0, 0, 0}, {1, 1, 1}), 10, 1);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<Vec3> ok{{0, 0, 0}};
  const std::vector<Vec3> bad{{nan, 0, 0}};
  CHECK_THROWS_AS(completeness(s, ok, 0.0), InvalidArgument);
  CHECK_THROWS_AS(completeness(s, ok, -1.0), InvalidArgument);
  CHECK_THROWS_AS(completeness(s, ok, nan), InvalidArgument);
  CHECK_THROWS_AS(completeness(s, bad, 0.003), InvalidArgument);
  CHECK_THROWS_AS(CoverageTracker(s, 0.0), InvalidArgument);
  CoverageTracker t(s, 0.5);
  CHECK_THROWS_AS(t.add(bad), InvalidArgument);
  CHECK(t.completeness().covered == 0);
}
