// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Purpose-built test objects (issue 18), generated procedurally and deterministically: objects whose contact with
/// the support hides surface no sensor above it can see, or that are hard for a stop rule — a box on four thin legs
/// (table), a body on four wheels (car), an open mug with a handle, a mushroom whose cap overhangs near the support,
/// a thin plate standing upright. World frame, metres, +z up, standing on z = 0 (the pedestal top), about 0.16 m
/// across like the benchmark objects. Each object is a union of closed, consistently oriented (outward,
/// counter-clockwise) triangle meshes, one per part; parts touch or overlap, so the mesh as a whole has internal
/// faces (the ground truth counts them unobservable). data/meshes/test-objects/ holds the same meshes as OBJ files
/// (`test_object_obj`; tests/sim/test_test_objects.cpp checks the files against this generator and rewrites them
/// with NBS_WRITE_TEST_OBJECTS=DIR).

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "nbs/mesh/indexed_mesh.hpp"

namespace nbs {

/// The five test objects.
enum class TestObject : std::uint8_t { table, car, mug, mushroom, plate };

/// Every TestObject in enum order.
inline constexpr std::array<TestObject, 5> kTestObjects{TestObject::table, TestObject::car, TestObject::mug,
                                                        TestObject::mushroom, TestObject::plate};

/// File stem of each object in data/meshes/test-objects/ ("table", "car", "mug", "mushroom", "plate").
[[nodiscard]] constexpr std::string_view test_object_name(TestObject o) {
  constexpr std::array<std::string_view, 5> names{"table", "car", "mug", "mushroom", "plate"};
  return names[static_cast<std::size_t>(o)];
}

namespace detail {

/// Appends a part (vertices + triangles indexing them from 0) to `m`.
inline void append_part(IndexedMesh& m, const std::vector<Vec3>& v, const std::vector<IndexedMesh::Triangle>& f) {
  const auto o = static_cast<std::uint32_t>(m.vertices.size());
  m.vertices.insert(m.vertices.end(), v.begin(), v.end());
  for (const auto& t : f) m.triangles.push_back({t[0] + o, t[1] + o, t[2] + o});
}

/// Closed axis-aligned box [lo, hi] (m), 8 vertices, 12 outward triangles.
inline void add_box(IndexedMesh& m, const Vec3& lo, const Vec3& hi) {
  const double x0 = lo.x(), y0 = lo.y(), z0 = lo.z(), x1 = hi.x(), y1 = hi.y(), z1 = hi.z();
  append_part(m,
              {{x0, y0, z0}, {x1, y0, z0}, {x1, y1, z0}, {x0, y1, z0}, {x0, y0, z1}, {x1, y0, z1}, {x1, y1, z1},
               {x0, y1, z1}},
              {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4}, {1, 2, 6}, {1, 6, 5}, {2, 3, 7},
               {2, 7, 6}, {3, 0, 4}, {3, 4, 7}});
}

/// Closed cylinder from `base` along the unit `axis`, radius r, height h (m): an n-gon prism with centre-fanned caps.
inline void add_cylinder(IndexedMesh& m, const Vec3& base, const Vec3& axis, double r, double h, std::uint32_t n = 48) {
  const Vec3 a = axis.normalized();
  const Vec3 t = std::abs(a.x()) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
  const Vec3 u = a.cross(t).normalized();
  const Vec3 w = a.cross(u);  // (u, w, a) right-handed
  std::vector<Vec3> v;
  for (const double k : {0.0, h})
    for (std::uint32_t i = 0; i < n; ++i) {
      const double s = 2 * std::numbers::pi * i / n;
      v.push_back(base + k * a + r * (std::cos(s) * u + std::sin(s) * w));
    }
  v.push_back(base);
  v.push_back(base + h * a);
  std::vector<IndexedMesh::Triangle> f;
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t i1 = (i + 1) % n;
    f.push_back({i, i1, n + i1});
    f.push_back({i, n + i1, n + i});
    f.push_back({2 * n, i1, i});
    f.push_back({2 * n + 1, n + i, n + i1});
  }
  append_part(m, v, f);
}

/// An open cup about the z axis (m): outer wall r_out from z0 to z1, rim, inner wall r_in down to the inner floor
/// at z0 + floor, outer bottom; n-gon rings.
inline void add_cup(IndexedMesh& m, double z0, double z1, double r_out, double r_in, double floor,
                    std::uint32_t n = 64) {
  std::vector<Vec3> v;
  for (const auto& [r, z] : {std::pair{r_out, z0}, {r_out, z1}, {r_in, z1}, {r_in, z0 + floor}})
    for (std::uint32_t i = 0; i < n; ++i) {
      const double s = 2 * std::numbers::pi * i / n;
      v.emplace_back(r * std::cos(s), r * std::sin(s), z);
    }
  v.emplace_back(0.0, 0.0, z0);
  v.emplace_back(0.0, 0.0, z0 + floor);
  std::vector<IndexedMesh::Triangle> f;
  for (std::uint32_t k = 0; k < 3; ++k)
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint32_t i1 = (i + 1) % n, a = k * n + i, b = k * n + i1, c = (k + 1) * n + i1, d = (k + 1) * n + i;
      f.push_back({a, b, c});
      f.push_back({a, c, d});
    }
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t i1 = (i + 1) % n;
    f.push_back({4 * n, i1, i});
    f.push_back({4 * n + 1, 3 * n + i, 3 * n + i1});
  }
  append_part(m, v, f);
}

/// Torus in the x–z plane (axis y) about `c`: major radius R, minor r (m), n × k quads.
inline void add_torus(IndexedMesh& m, const Vec3& c, double big_r, double r, std::uint32_t n = 48,
                      std::uint32_t k = 16) {
  std::vector<Vec3> v;
  for (std::uint32_t i = 0; i < n; ++i) {
    const double s = 2 * std::numbers::pi * i / n;
    for (std::uint32_t j = 0; j < k; ++j) {
      const double p = 2 * std::numbers::pi * j / k, rr = big_r + r * std::cos(p);
      v.emplace_back(c.x() + rr * std::cos(s), c.y() + r * std::sin(p), c.z() + rr * std::sin(s));
    }
  }
  std::vector<IndexedMesh::Triangle> f;
  for (std::uint32_t i = 0; i < n; ++i)
    for (std::uint32_t j = 0; j < k; ++j) {
      const std::uint32_t a = i * k + j, b = i * k + (j + 1) % k, cc = ((i + 1) % n) * k + (j + 1) % k,
                          d = ((i + 1) % n) * k + j;
      f.push_back({a, cc, d});  // outward: (b − a) × (d − a) points away from the tube's axis
      f.push_back({a, b, cc});
    }
  append_part(m, v, f);
}

}  // namespace detail

/// One line describing object `o` with its dimensions (the OBJ file's first comment).
[[nodiscard]] constexpr std::string_view test_object_description(TestObject o) {
  constexpr std::array<std::string_view, 5> what{
      "a box on four thin legs (16 x 10 cm top at 8-11 cm, legs 12 mm square)",
      "a body on four wheels (16 x 7 cm body 2.5 cm above the support, wheels r 22 mm beside it)",
      "an open mug with a handle (r 4 cm, wall 4 mm, 10 cm high; handle a torus R 24 mm, r 6 mm)",
      "a mushroom: stem r 16 mm, a cap r 7 cm whose underside overhangs 3.5 cm above the support",
      "a thin plate standing upright (16 x 12 cm, 6 mm thick)"};
  return what[static_cast<std::size_t>(o)];
}

/// The mesh of test object `o` (file comment; dimensions in test_object_description). Deterministic.
[[nodiscard]] inline IndexedMesh make_test_object(TestObject o) {
  IndexedMesh m;
  switch (o) {
    case TestObject::table:  // top 16 x 10 x 3 cm at z 8..11 cm; legs 12 mm square under it, touching it
      detail::add_box(m, {-0.08, -0.05, 0.08}, {0.08, 0.05, 0.11});
      for (const int sx : {-1, 1})
        for (const int sy : {-1, 1}) {
          const double x = sx * 0.068, y = sy * 0.038;
          detail::add_box(m, {x - 0.006, y - 0.006, 0.0}, {x + 0.006, y + 0.006, 0.08});
        }
      break;
    case TestObject::car:  // body 16 x 7 x 4.5 cm from z 2.5 cm, cab on it; wheels r 22 mm, 16 mm wide, on its sides
      detail::add_box(m, {-0.08, -0.035, 0.025}, {0.08, 0.035, 0.07});
      detail::add_box(m, {-0.035, -0.03, 0.07}, {0.04, 0.03, 0.1});
      for (const double x : {-0.05, 0.05})
        for (const int sy : {-1, 1}) detail::add_cylinder(m, {x, sy * 0.035, 0.022}, {0.0, sy * 1.0, 0.0}, 0.022, 0.016);
      break;
    case TestObject::mug:  // cup r 4 cm, wall 4 mm, floor 6 mm, 10 cm high; torus handle overlapping the wall
      detail::add_cup(m, 0.0, 0.1, 0.04, 0.036, 0.006);
      detail::add_torus(m, {0.058, 0.0, 0.05}, 0.024, 0.006);
      break;
    case TestObject::mushroom:  // stem r 16 mm, z 0..4 cm; cap r 7 cm, z 3.5..6.5 cm (the stem enters it by 5 mm)
      detail::add_cylinder(m, {0.0, 0.0, 0.0}, {0.0, 0.0, 1.0}, 0.016, 0.04);
      detail::add_cylinder(m, {0.0, 0.0, 0.035}, {0.0, 0.0, 1.0}, 0.07, 0.03, 72);
      break;
    case TestObject::plate:  // 16 x 0.6 x 12 cm, standing on its long edge
      detail::add_box(m, {-0.08, -0.003, 0.0}, {0.08, 0.003, 0.12});
      break;
  }
  return m;
}

/// `m` as OBJ text: the comment lines, then "v x y z" (metres, 6 decimals) and "f a b c" (1-based) lines.
[[nodiscard]] inline std::string obj_text(const IndexedMesh& m, std::string_view comment) {
  std::string s = "# " + std::string(comment) + "\n# generated by include/nbs/sim/test_objects.hpp; metres, z up\n";
  char line[96];
  for (const Vec3& v : m.vertices) {
    std::snprintf(line, sizeof line, "v %.6f %.6f %.6f\n", v.x(), v.y(), v.z());
    s += line;
  }
  for (const auto& t : m.triangles) {
    std::snprintf(line, sizeof line, "f %u %u %u\n", t[0] + 1, t[1] + 1, t[2] + 1);
    s += line;
  }
  return s;
}

/// The OBJ file of test object `o` as in data/meshes/test-objects/.
[[nodiscard]] inline std::string test_object_obj(TestObject o) {
  return obj_text(make_test_object(o), test_object_description(o));
}

}  // namespace nbs
