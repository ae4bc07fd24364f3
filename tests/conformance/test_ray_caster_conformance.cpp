// SPDX-License-Identifier: BSD-3-Clause
// RayCaster conformance (core): BruteForceRayCaster and a minimal user-written analytic caster, against the
// brute-force oracle (nbs::embree::Scene: test_conformance_embree).
#include "ray_caster_conformance.hpp"

#include "../embree/analytic_meshes.hpp"

namespace {

using nbs::Vec3;

/// The user-written caster: the square [−h, h]² at z = z0 as plane_mesh(h, z0, 1) stores it (triangle 0 where
/// y ≤ x, triangle 1 where y ≥ x, normals +z).
struct SquareCaster {
  double h = 0.05, z0 = 0.02;
  [[nodiscard]] std::optional<nbs::RayHit> first_hit(const Vec3& o, const Vec3& d, double max_distance) const {
    if (d.z() == 0.0) return std::nullopt;
    const double t = (z0 - o.z()) / d.z();
    const Vec3 p = o + t * d;
    if (!(t > 0.0 && t <= max_distance) || std::abs(p.x()) > h || std::abs(p.y()) > h) return std::nullopt;
    return nbs::RayHit{t, p.y() <= p.x() ? 0u : 1u, Vec3::UnitZ()};
  }
};

}  // namespace

TEST_CASE("RayCaster conformance: BruteForceRayCaster on a sphere and a plane", "[conformance][raycaster]") {
  nbs::IndexedMesh sphere = nbs_test::sphere_mesh(Vec3(0, 0, 0.04), 0.04, 8);
  const nbs::BruteForceRayCaster a(sphere);
  nbs::conformance::check_ray_caster_conformance(a, sphere);
  const nbs::IndexedMesh plane = nbs_test::plane_mesh(0.05, 0.0, 4);
  const nbs::BruteForceRayCaster b(plane);
  nbs::conformance::check_ray_caster_conformance(b, plane, {}, 2);
}

TEST_CASE("RayCaster conformance: a user-written analytic caster", "[conformance][raycaster]") {
  const SquareCaster square;
  const nbs::IndexedMesh mesh = nbs_test::plane_mesh(square.h, square.z0, 1);
  REQUIRE(mesh.triangles.size() == 2);
  nbs::conformance::check_ray_caster_conformance(square, mesh, {}, 3);
}
