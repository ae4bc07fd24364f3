// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Shared oracles for the mesh tests: brute-force coverage and normal agreement against analytic shapes.

#include <cmath>
#include <vector>

#include "analytic_scanner.hpp"
#include "nbs/mesh/streaming_mesh.hpp"

namespace nbs::test {

/// Sensor looking straight down (−z) from (x, y, height); stripe along world x, moving along world −y.
inline Viewpoint down_at(double x, double y, double height) {
  return Viewpoint::from_axes(Vec3(1, 0, 0), Vec3(0, -1, 0), Vec3(0, 0, -1), Vec3(x, y, height));
}

/// c_a: fraction of `samples` within `radius` of a vertex that belongs to a triangle (brute force).
template <class M>
double coverage(const M& mesh, const std::vector<Vec3>& samples, double radius) {
  std::vector<Vec3> verts;
  for (VertexId v = 0; v < mesh.vertex_count(); ++v)
    if (mesh.in_triangle(v)) verts.push_back(mesh.position(v));
  std::size_t covered = 0;
  for (const Vec3& s : samples) {
    for (const Vec3& v : verts)
      if ((v - s).squaredNorm() <= radius * radius) {
        ++covered;
        break;
      }
  }
  return samples.empty() ? 0.0 : static_cast<double>(covered) / static_cast<double>(samples.size());
}

/// Fraction of triangulated vertices whose normal is within `max_angle_rad` of the analytic normal; vertices
/// closer than `exclude_m` to a sharp edge (predicate) are skipped.
template <class M, class Skip>
double normal_agreement(const M& mesh, const Shape& shape, double max_angle_rad, Skip&& skip) {
  std::size_t n = 0, good = 0;
  for (VertexId v = 0; v < mesh.vertex_count(); ++v) {
    if (!mesh.in_triangle(v) || skip(mesh.position(v))) continue;
    ++n;
    good += mesh.normal(v).dot(shape.normal_at(mesh.position(v))) >= std::cos(max_angle_rad) ? 1 : 0;
  }
  return n == 0 ? 0.0 : static_cast<double>(good) / static_cast<double>(n);
}

}  // namespace nbs::test
