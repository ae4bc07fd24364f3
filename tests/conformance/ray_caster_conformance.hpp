// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Conformance harness for nbs::RayCaster (include/nbs/sim/ray_caster.hpp). Checked contract on seeded random rays
// (origins in a box around the mesh, directions uniform, half of them aimed at a random surface point):
//  - first_hit agrees with BruteForceRayCaster (the oracle): hit or miss, distance (within `distance_tol_m`), the
//    triangle, and the unit geometric normal of that triangle as stored; rays whose oracle hit or caster hit lies
//    within `edge_tol` (barycentric) of a triangle edge, or that graze a triangle, are not judged (a float caster
//    may pick either neighbour, or catch an edge the double-precision oracle just misses);
//  - hits are at distance > 0 and ≤ max_distance: with max_distance just below the oracle's hit distance, no hit;
//  - const calls may run concurrently: two threads get the sequential answers.
#include "nbs_catch.hpp"

#include <cmath>
#include <optional>
#include <random>
#include <thread>
#include <vector>

#include "nbs/sim/ray_caster.hpp"
#include "nbs_random.hpp"

namespace nbs::conformance {

struct RayCase {
  int rays = 400;
  double distance_tol_m = 1e-5;
  double edge_tol = 1e-4;
  double box_margin_m = 0.05;  ///< origins are drawn from the mesh bounds grown by this
};

namespace detail {
struct TestRay {
  Vec3 o, d;
};
/// Barycentric distance of the oracle hit to its triangle's edges and |cos| of the ray–normal angle.
inline bool well_conditioned(const IndexedMesh& m, const TestRay& r, const RayHit& h, double edge_tol) {
  const Vec3 p = r.o + h.distance * r.d;
  const Vec3 a = m.corner(h.triangle, 0), b = m.corner(h.triangle, 1), c = m.corner(h.triangle, 2);
  const Vec3 n = (b - a).cross(c - a);
  const double area2 = n.squaredNorm();
  const double u = (c - b).cross(p - b).dot(n) / area2, v = (a - c).cross(p - c).dot(n) / area2;
  const double w = 1.0 - u - v;
  return std::min({u, v, w}) > edge_tol && std::abs(r.d.dot(n.normalized())) > 1e-3;
}
}  // namespace detail

template <class R>
void check_ray_caster_conformance(const R& caster, const IndexedMesh& mesh, const RayCase& c = {},
                                  std::uint64_t seed = 1) {
  static_assert(RayCaster<R>);
  const BruteForceRayCaster oracle(mesh);
  const Aabb box = mesh.bounds();
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> g;
  std::uniform_int_distribution<std::size_t> tri(0, mesh.triangles.size() - 1);
  std::vector<detail::TestRay> rays;
  for (int i = 0; i < c.rays; ++i) {
    Vec3 o;
    for (int a = 0; a < 3; ++a)
      o[a] = box.min[a] - c.box_margin_m + u(rng) * (box.max[a] - box.min[a] + 2 * c.box_margin_m);
    Vec3 d = nbs_test::random_vec3(g, rng);
    if (i % 2 == 0) {  // aim at a random point of a random triangle
      const std::size_t t = tri(rng);
      double s1 = u(rng), s2 = u(rng);
      if (s1 + s2 > 1.0) s1 = 1.0 - s1, s2 = 1.0 - s2;
      const Vec3 target = mesh.corner(t, 0) + s1 * (mesh.corner(t, 1) - mesh.corner(t, 0)) +
                          s2 * (mesh.corner(t, 2) - mesh.corner(t, 0));
      if ((target - o).norm() > 1e-6) d = target - o;
    }
    rays.push_back({o, d.normalized()});
  }
  std::vector<std::optional<RayHit>> got(rays.size());
  int hits = 0, misses = 0, judged = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const auto& r = rays[i];
    got[i] = caster.first_hit(r.o, r.d, std::numeric_limits<double>::infinity());
    const std::optional<RayHit> want = oracle.first_hit(r.o, r.d);
    INFO("ray " << i << " o (" << r.o.transpose() << ") d (" << r.d.transpose() << ")");
    if (want && !detail::well_conditioned(mesh, r, *want, c.edge_tol)) continue;
    if (got[i]) REQUIRE(got[i]->triangle < mesh.triangles.size());
    if (got[i] && !detail::well_conditioned(mesh, r, *got[i], c.edge_tol)) continue;  // grazes an edge of its hit
    ++judged;
    REQUIRE(got[i].has_value() == want.has_value());
    if (!want) {
      ++misses;
      continue;
    }
    ++hits;
    CHECK(got[i]->distance > 0.0);
    CHECK(got[i]->distance == Approx(want->distance).margin(c.distance_tol_m));
    CHECK(got[i]->triangle == want->triangle);
    CHECK(got[i]->normal.norm() == Approx(1.0).margin(1e-6));
    CHECK(got[i]->normal.dot(want->normal) == Approx(1.0).margin(1e-6));
    // max_distance: just short of the hit, nothing; just beyond, the same hit.
    if (want->distance < 20 * c.distance_tol_m) continue;
    CHECK_FALSE(caster.first_hit(r.o, r.d, want->distance - 10 * c.distance_tol_m).has_value());
    const auto far = caster.first_hit(r.o, r.d, want->distance + 10 * c.distance_tol_m);
    REQUIRE(far.has_value());
    CHECK(far->triangle == want->triangle);
  }
  CHECK(judged >= c.rays * 9 / 10);
  CHECK(hits >= c.rays / 5);
  CHECK(misses >= c.rays / 20);
  // Concurrent const calls.
  std::vector<std::vector<std::optional<RayHit>>> par(2, std::vector<std::optional<RayHit>>(rays.size()));
  {
    std::vector<std::thread> threads;
    for (std::size_t t = 0; t < par.size(); ++t)
      threads.emplace_back([&, t] {
        for (std::size_t i = 0; i < rays.size(); ++i)
          par[t][i] = caster.first_hit(rays[i].o, rays[i].d, std::numeric_limits<double>::infinity());
      });
    for (auto& th : threads) th.join();
  }
  for (const auto& p : par)
    for (std::size_t i = 0; i < rays.size(); ++i) {
      REQUIRE(p[i].has_value() == got[i].has_value());
      if (p[i]) CHECK((p[i]->distance == got[i]->distance && p[i]->triangle == got[i]->triangle));
    }
}

}  // namespace nbs::conformance
