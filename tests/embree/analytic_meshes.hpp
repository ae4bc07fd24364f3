// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Finely tessellated analytic surfaces for scanner tests.
#include <cmath>
#include <numbers>

#include "nbs/mesh/indexed_mesh.hpp"

namespace nbs_test {

/// Square [−h, h]² in the plane z = z0, n × n cells, two triangles each, facing +z.
inline nbs::IndexedMesh plane_mesh(double half, double z0, int n = 20) {
  nbs::IndexedMesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.vertices.emplace_back(-half + 2 * half * i / n, -half + 2 * half * j / n, z0);
  auto id = [n](int i, int j) { return static_cast<std::uint32_t>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return m;
}

/// UV sphere of radius r about c with `rings` latitude bands and 2·rings longitude segments.
/// Every surface point lies within r (1 − cos(√2 π / (2 rings))) of the sphere (half a cell diagonal).
inline nbs::IndexedMesh sphere_mesh(const nbs::Vec3& c, double r, int rings) {
  nbs::IndexedMesh m;
  const int segs = 2 * rings;
  for (int i = 0; i <= rings; ++i) {
    const double th = std::numbers::pi * i / rings;
    for (int j = 0; j < segs; ++j) {
      const double ph = 2 * std::numbers::pi * j / segs;
      m.vertices.push_back(c + r * nbs::Vec3(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)));
    }
  }
  auto id = [segs](int i, int j) { return static_cast<std::uint32_t>(i * segs + (j % segs)); };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segs; ++j) {
      m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return m;
}

}  // namespace nbs_test
