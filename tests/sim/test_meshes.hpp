// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Small analytic test meshes for the sim tests.

#include <cmath>
#include <numbers>

#include "nbs/mesh/indexed_mesh.hpp"

namespace nbs::test {

/// Appends the quad (a, b, c, d) (in order around its boundary) as two triangles.
inline void add_quad(IndexedMesh& m, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const auto base = static_cast<std::uint32_t>(m.vertices.size());
  m.vertices.insert(m.vertices.end(), {a, b, c, d});
  m.triangles.push_back({base, base + 1, base + 2});
  m.triangles.push_back({base, base + 2, base + 3});
}

/// Axis-aligned box [lo, hi] as 12 triangles (outward orientation).
inline IndexedMesh box_mesh(const Vec3& lo, const Vec3& hi) {
  IndexedMesh m;
  const auto p = [&](int x, int y, int z) { return Vec3(x ? hi.x() : lo.x(), y ? hi.y() : lo.y(), z ? hi.z() : lo.z()); };
  add_quad(m, p(0, 0, 0), p(0, 1, 0), p(1, 1, 0), p(1, 0, 0));  // bottom
  add_quad(m, p(0, 0, 1), p(1, 0, 1), p(1, 1, 1), p(0, 1, 1));  // top
  add_quad(m, p(0, 0, 0), p(1, 0, 0), p(1, 0, 1), p(0, 0, 1));  // -y
  add_quad(m, p(0, 1, 0), p(0, 1, 1), p(1, 1, 1), p(1, 1, 0));  // +y
  add_quad(m, p(0, 0, 0), p(0, 0, 1), p(0, 1, 1), p(0, 1, 0));  // -x
  add_quad(m, p(1, 0, 0), p(1, 1, 0), p(1, 1, 1), p(1, 0, 1));  // +x
  return m;
}

/// UV sphere of radius r around c with `rings` latitude bands and `segments` longitude segments; vertices lie on
/// the sphere.
inline IndexedMesh uv_sphere(const Vec3& c, double r, int rings, int segments) {
  IndexedMesh m;
  for (int i = 0; i <= rings; ++i) {
    const double th = std::numbers::pi * i / rings;
    for (int j = 0; j < segments; ++j) {
      const double ph = 2.0 * std::numbers::pi * j / segments;
      m.vertices.push_back(c + r * Vec3(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)));
    }
  }
  const auto v = [&](int i, int j) { return static_cast<std::uint32_t>(i * segments + (j % segments)); };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      if (i > 0) m.triangles.push_back({v(i, j), v(i + 1, j), v(i, j + 1)});
      if (i + 1 < rings) m.triangles.push_back({v(i, j + 1), v(i + 1, j), v(i + 1, j + 1)});
    }
  return m;
}

/// Cube [0, s]³ standing on z = 0 with a square well of width w and depth d centred in its top face.
inline IndexedMesh cube_with_well(double s, double w, double d) {
  IndexedMesh m;
  const double a = 0.5 * (s - w), b = 0.5 * (s + w), h = s - d;
  add_quad(m, {0, 0, 0}, {0, s, 0}, {s, s, 0}, {s, 0, 0});  // bottom
  add_quad(m, {0, 0, 0}, {s, 0, 0}, {s, 0, s}, {0, 0, s});  // outer sides
  add_quad(m, {0, s, 0}, {0, s, s}, {s, s, s}, {s, s, 0});
  add_quad(m, {0, 0, 0}, {0, 0, s}, {0, s, s}, {0, s, 0});
  add_quad(m, {s, 0, 0}, {s, s, 0}, {s, s, s}, {s, 0, s});
  add_quad(m, {0, 0, s}, {s, 0, s}, {b, a, s}, {a, a, s});  // top ring (4 trapezoids)
  add_quad(m, {s, 0, s}, {s, s, s}, {b, b, s}, {b, a, s});
  add_quad(m, {s, s, s}, {0, s, s}, {a, b, s}, {b, b, s});
  add_quad(m, {0, s, s}, {0, 0, s}, {a, a, s}, {a, b, s});
  add_quad(m, {a, a, s}, {b, a, s}, {b, a, h}, {a, a, h});  // well walls
  add_quad(m, {b, a, s}, {b, b, s}, {b, b, h}, {b, a, h});
  add_quad(m, {b, b, s}, {a, b, s}, {a, b, h}, {b, b, h});
  add_quad(m, {a, b, s}, {a, a, s}, {a, a, h}, {a, b, h});
  add_quad(m, {a, a, h}, {b, a, h}, {b, b, h}, {a, b, h});  // well bottom
  return m;
}

}  // namespace nbs::test
