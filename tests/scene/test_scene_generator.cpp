// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include <algorithm>
#include <limits>

#include "nbs/scene/scene_generator.hpp"
#include "test_meshes.hpp"

using namespace nbs;
using namespace nbs::scene;
using nbs::detail::Vec2;

namespace {
std::vector<ObjectSpec> six_objects() {
  return {{"box_a", test::box_mesh(Vec3(-0.05, -0.03, 0.0), Vec3(0.05, 0.03, 0.12))},
          {"ball", test::uv_sphere(Vec3(0.0, 0.0, 0.04), 0.04, 10, 16)},
          {"box_b", test::box_mesh(Vec3(0.0, 0.0, 0.0), Vec3(0.08, 0.02, 0.05))},  // origin at a corner
          {"well", test::cube_with_well(0.07, 0.03, 0.03)},
          {"box_c", test::box_mesh(Vec3(-0.02, -0.02, -0.1), Vec3(0.02, 0.02, 0.0))},  // below its origin
          {"ball_small", test::uv_sphere(Vec3(0.1, 0.1, 0.1), 0.025, 8, 12)}};
}

/// Brute-force xy distance of two placed objects from their world-frame vertices: 0 if a vertex of one lies in the
/// other's footprint or two footprint edges cross, else the least vertex-to-edge distance both ways.
double brute_force_gap(const PlacedObject& a, const PlacedObject& b) {
  const auto inside = [](const Vec2& q, const std::vector<Vec2>& h) {
    for (std::size_t i = 0; i < h.size(); ++i)
      if (nbs::detail::cross2(h[i], h[(i + 1) % h.size()], q) < 0.0) return false;
    return true;
  };
  for (const Vec3& v : a.mesh.vertices)
    if (inside(v.head<2>(), b.footprint)) return 0.0;
  for (const Vec3& v : b.mesh.vertices)
    if (inside(v.head<2>(), a.footprint)) return 0.0;
  double best = std::numeric_limits<double>::infinity();
  for (const auto* p : {&a, &b}) {
    const auto* q = p == &a ? &b : &a;
    for (const Vec3& v : p->mesh.vertices)
      for (std::size_t i = 0; i < q->footprint.size(); ++i)
        best = std::min(best, nbs::detail::point_segment_distance(v.head<2>(), q->footprint[i],
                                                                   q->footprint[(i + 1) % q->footprint.size()]));
  }
  return best;
}

void check_scene(const SimulatedScene& s, std::size_t n) {
  REQUIRE(s.objects.size() == n);
  const double hx = 0.5 * s.settings.table_size_x_m + 1e-12, hy = 0.5 * s.settings.table_size_y_m + 1e-12;
  for (const auto& o : s.objects) {
    CAPTURE(o.name);
    CHECK(std::abs(o.mesh.bounds().min.z() - s.settings.table_height_m) < 1e-12);  // standing on the table
    CHECK(std::abs(o.T_world_object.linear().col(2).z() - 1.0) < 1e-12);           // upright: yaw only
    for (const Vec3& v : o.mesh.vertices) {
      CHECK(std::abs(v.x()) <= hx);
      CHECK(std::abs(v.y()) <= hy);
      // the footprint holds every vertex (within rounding)
      for (std::size_t i = 0; i < o.footprint.size(); ++i)
        REQUIRE(nbs::detail::cross2(o.footprint[i], o.footprint[(i + 1) % o.footprint.size()], v.head<2>()) > -1e-12);
    }
  }
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      CAPTURE(i, j);
      CHECK(brute_force_gap(s.objects[i], s.objects[j]) >= s.settings.min_gap_m - 1e-12);
    }
}
}  // namespace

TEST_CASE("generate_scene: upright, on the table, footprints at least min_gap_m apart", "[scene][generator]") {
  const auto objects = six_objects();
  SceneSettings st;
  st.table_height_m = 0.72;
  st.table_size_x_m = 0.5;
  st.table_size_y_m = 0.4;
  st.min_gap_m = 0.01;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    CAPTURE(seed);
    const SimulatedScene s = generate_scene(objects, st, seed);
    check_scene(s, objects.size());
    // the object's mesh is the spec's under T_world_object
    for (std::size_t k = 0; k < objects.size(); ++k)
      CHECK((s.objects[k].T_world_object * objects[k].mesh.vertices[3] - s.objects[k].mesh.vertices[3]).norm() < 1e-12);
    const LabeledMesh m = s.combined_mesh();
    CHECK(m.mesh.triangles.size() == m.triangle_object.size());
    CHECK(std::count(m.triangle_object.begin(), m.triangle_object.end(), -1) == 2);
    CHECK(std::count(m.triangle_object.begin(), m.triangle_object.end(), 3) ==
          static_cast<std::ptrdiff_t>(objects[3].mesh.triangles.size()));
    CHECK_NOTHROW(m.mesh.validate());
  }
}

TEST_CASE("generate_scene: deterministic for a seed, different for another", "[scene][generator]") {
  const auto objects = six_objects();
  const SimulatedScene a = generate_scene(objects, SceneSettings{}, 11);
  const SimulatedScene b = generate_scene(objects, SceneSettings{}, 11);
  const SimulatedScene c = generate_scene(objects, SceneSettings{}, 12);
  for (std::size_t k = 0; k < objects.size(); ++k) {
    CHECK(a.objects[k].T_world_object.matrix() == b.objects[k].T_world_object.matrix());
    CHECK(a.objects[k].mesh.vertices == b.objects[k].mesh.vertices);
  }
  CHECK(a.objects[0].T_world_object.matrix() != c.objects[0].T_world_object.matrix());
}

TEST_CASE("generate_scene: close scenes keep min_gap_m and have a neighbour within max_gap_m", "[scene][generator]") {
  const auto objects = six_objects();
  SceneSettings st;
  st.min_gap_m = 0.003;
  st.max_gap_m = 0.012;
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    const SimulatedScene s = generate_scene(objects, st, seed);
    check_scene(s, objects.size());
    for (std::size_t i = 1; i < s.objects.size(); ++i) {
      double nearest = std::numeric_limits<double>::infinity();
      for (std::size_t j = 0; j < i; ++j)
        nearest = std::min(nearest, nbs::detail::convex_distance(s.objects[i].footprint, s.objects[j].footprint));
      CHECK(nearest <= *st.max_gap_m);
    }
  }
}

TEST_CASE("generate_scene: bad input", "[scene][generator]") {
  std::vector<ObjectSpec> many(40, ObjectSpec{"cube", test::box_mesh(Vec3::Zero(), Vec3::Constant(0.1))});
  SceneSettings st;
  st.table_size_x_m = 0.3;
  st.table_size_y_m = 0.3;
  st.max_attempts = 200;
  CHECK_THROWS_WITH(generate_scene(many, st, 1), nbs_test::Contains("of 40 objects on the 0.3 x 0.3 m table"));
  std::vector<ObjectSpec> huge{{"slab", test::box_mesh(Vec3::Zero(), Vec3(1.0, 1.0, 0.01))}};
  CHECK_THROWS_WITH(generate_scene(huge, st, 1), nbs_test::Contains("\"slab\""));
  CHECK_THROWS_WITH(generate_scene(std::vector<ObjectSpec>{}, SceneSettings{}, 1), nbs_test::Contains("no objects"));
  st.min_gap_m = -0.001;
  CHECK_THROWS_WITH(generate_scene(many, st, 1), nbs_test::Contains("min_gap_m"));
  st = {};
  st.max_gap_m = 0.001;
  CHECK_THROWS_WITH(generate_scene(many, st, 1), nbs_test::Contains("max_gap_m"));
  std::vector<ObjectSpec> empty_mesh{{"nothing", IndexedMesh{}}};
  CHECK_THROWS_WITH(generate_scene(empty_mesh, SceneSettings{}, 1), nbs_test::Contains("empty"));
}
