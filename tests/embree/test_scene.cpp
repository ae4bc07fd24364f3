// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include <random>
#include <vector>

#include "analytic_meshes.hpp"
#include "nbs/embree/scene.hpp"
#include "nbs_random.hpp"

using nbs::Vec3;

TEST_CASE("Embree scene agrees with the brute-force ray caster", "[embree][scene]") {
  const nbs::IndexedMesh mesh = nbs_test::sphere_mesh({0.01, -0.02, 0.1}, 0.05, 12);
  const nbs::BruteForceRayCaster oracle(mesh);
  const nbs::embree::Scene scene(mesh);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Vec3 origin(0.2, 0.1, 0.25);
  std::vector<Vec3> dirs;
  for (int i = 0; i < 3000; ++i) {
    const Vec3 target = Vec3(0.01, -0.02, 0.1) + 0.07 * nbs_test::random_vec3(u, rng);
    dirs.push_back((target - origin).normalized());
  }
  std::vector<float> packet(dirs.size()), single(dirs.size());
  scene.cast_fan(origin, dirs, 1.0, packet, nbs::embree::RayMode::packet);
  scene.cast_fan(origin, dirs, 1.0, single, nbs::embree::RayMode::single);
  int hits = 0, disagreements = 0;
  for (std::size_t i = 0; i < dirs.size(); ++i) {
    const auto want = oracle.first_hit(origin, dirs[i], 1.0);
    const auto got = scene.first_hit(origin, dirs[i], 1.0);
    CHECK(packet[i] == single[i]);
    if (want.has_value() != got.has_value()) {  // only rays grazing an edge may disagree (float vs double)
      ++disagreements;
      continue;
    }
    if (!want) {
      CHECK(std::isinf(packet[i]));
      continue;
    }
    ++hits;
    CHECK(got->distance == Approx(want->distance).margin(1e-6));
    CHECK(packet[i] == Approx(want->distance).margin(1e-6));
    if (got->triangle == want->triangle) CHECK(got->normal.isApprox(want->normal, 1e-5));
  }
  CHECK(hits > 1000);
  CHECK(disagreements <= 3);
}

TEST_CASE("Embree scene: max distance, bad meshes, move semantics", "[embree][scene][bad-input]") {
  const nbs::IndexedMesh plane = nbs_test::plane_mesh(1.0, 0.0, 2);
  nbs::embree::Scene scene(plane);
  CHECK(scene.packet_width() >= 1);
  const auto hit = scene.first_hit({0.1, 0.2, 0.5}, -Vec3::UnitZ(), 1.0);
  REQUIRE(hit);
  CHECK(hit->distance == Approx(0.5));
  CHECK(std::abs(hit->normal.z()) == Approx(1.0));
  CHECK_FALSE(scene.first_hit({0.1, 0.2, 0.5}, -Vec3::UnitZ(), 0.4));
  CHECK_FALSE(scene.first_hit({0.1, 0.2, 0.5}, Vec3::UnitZ()));

  nbs::embree::Scene moved(std::move(scene));
  CHECK(moved.first_hit({0, 0, 1}, -Vec3::UnitZ()));
  nbs::embree::Scene other(nbs_test::plane_mesh(1.0, 0.3, 2));
  other = std::move(moved);
  CHECK(other.first_hit({0, 0, 1}, -Vec3::UnitZ())->distance == Approx(1.0));

  CHECK_THROWS_AS(nbs::embree::Scene(nbs::IndexedMesh{}), nbs::InvalidArgument);
  nbs::IndexedMesh bad = plane;
  bad.triangles.push_back({0, 1, 99});
  CHECK_THROWS_WITH(nbs::embree::Scene(bad), nbs_test::Contains("refers to vertex 99"));
  bad = plane;
  bad.vertices[0].x() = 1e300;
  CHECK_THROWS_WITH(nbs::embree::Scene(bad), nbs_test::Contains("single precision"));
  std::vector<float> out(1);
  const std::vector<Vec3> two{Vec3::UnitZ(), Vec3::UnitZ()};
  CHECK_THROWS_AS(other.cast_fan(Vec3::Zero(), two, 1.0, out), nbs::InvalidArgument);
}
