// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Ground-truth colour (Sec. 5.3): the colour of a mesh surface point (barycentric interpolation of vertex colours),
/// a seeded procedural pattern for meshes without colour, and the mean colour error of a coloured model.
/// Textures (OBJ/MTL with UVs) are not supported: a ground-truth mesh has vertex colours or none.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "nbs/core/detail/parallel_for.hpp"
#include "nbs/core/detail/random.hpp"
#include "nbs/mesh/indexed_mesh.hpp"
#include "nbs/sim/mesh_distance.hpp"

namespace nbs {

/// Colour of the point `p` of triangle `t` of `mesh` (which must have colours): the vertex colours weighted by the
/// barycentric coordinates of p's projection onto the triangle's plane, clamped to the triangle, rounded per channel.
/// A zero-area triangle gives the colour of its corner nearest to p. Throws InvalidArgument if t is out of range or
/// the mesh has no colour per vertex.
[[nodiscard]] inline Rgb surface_color(const IndexedMesh& mesh, std::size_t t, const Vec3& p) {
  detail::require(t < mesh.triangles.size(), "surface_color: triangle ", t, " of ", mesh.triangles.size());
  detail::require(mesh.colors.size() == mesh.vertices.size(), "surface_color: the mesh has ", mesh.colors.size(),
                  " colours for ", mesh.vertices.size(), " vertices");
  const auto& tri = mesh.triangles[t];
  const Vec3 a = mesh.vertices[tri[0]], ab = mesh.vertices[tri[1]] - a, ac = mesh.vertices[tri[2]] - a;
  const Vec3 ap = p - a;
  const double d00 = ab.dot(ab), d01 = ab.dot(ac), d11 = ac.dot(ac), d20 = ap.dot(ab), d21 = ap.dot(ac);
  const double den = d00 * d11 - d01 * d01;
  double w[3];
  if (!(den > 1e-24 * std::max(d00, d11) * std::max(d00, d11))) {
    int best = 0;
    double best_d2 = INFINITY;
    for (int k = 0; k < 3; ++k) {
      const double d2 = (mesh.vertices[tri[static_cast<std::size_t>(k)]] - p).squaredNorm();
      if (d2 < best_d2) best = k, best_d2 = d2;
    }
    return mesh.colors[tri[static_cast<std::size_t>(best)]];
  }
  w[1] = std::max(0.0, (d11 * d20 - d01 * d21) / den);
  w[2] = std::max(0.0, (d00 * d21 - d01 * d20) / den);
  w[0] = std::max(0.0, 1.0 - w[1] - w[2]);
  const double sum = w[0] + w[1] + w[2];
  Rgb out{};
  for (std::size_t c = 0; c < 3; ++c) {
    double v = 0.0;
    for (std::size_t k = 0; k < 3; ++k) v += w[k] * mesh.colors[tri[k]][c];
    out[c] = static_cast<std::uint8_t>(std::clamp(std::lround(v / sum), 0L, 255L));
  }
  return out;
}

/// A seeded 3-D checker pattern as vertex colours, so that a mesh without colour can be scanned in colour: cells of
/// edge (bounding-box diagonal / 8), shifted by a seeded offset, alternate between two seeded colours (each channel
/// of the second differs from the first's by at least 96). One colour per vertex, by the vertex's cell.
[[nodiscard]] inline std::vector<Rgb> procedural_colors(const IndexedMesh& mesh, std::uint64_t seed) {
  mesh.validate();
  const Aabb box = mesh.bounds();
  const double cell = std::max(box.extent().norm() / 8.0, 1e-9);
  std::uint64_t s = seed;
  const auto next = [&s] { return s = detail::splitmix64(s); };
  Vec3 offset;
  for (int k = 0; k < 3; ++k) offset[k] = cell * static_cast<double>(next() >> 11) * 0x1.0p-53;
  Rgb c0{}, c1{};
  for (std::size_t k = 0; k < 3; ++k) {
    c0[k] = static_cast<std::uint8_t>(next() % 256);
    const int shift = 96 + static_cast<int>(next() % 32);  // 96 … 127, away from the nearer end of [0, 255]
    c1[k] = static_cast<std::uint8_t>(c0[k] >= 128 ? c0[k] - shift : c0[k] + shift);
  }
  std::vector<Rgb> out(mesh.vertices.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    const Vec3 q = ((mesh.vertices[i] - box.min + offset) / cell).array().floor();
    const auto parity = static_cast<long long>(q.x()) + static_cast<long long>(q.y()) + static_cast<long long>(q.z());
    out[i] = (parity & 1) == 0 ? c0 : c1;
  }
  return out;
}

/// Colour distance ‖a − b‖ / 255, the Euclidean distance of the 8-bit RGB triples scaled so that one channel's full
/// range is 1 (so the range is [0, √3]).
[[nodiscard]] inline double color_distance(const Rgb& a, const Rgb& b) {
  double s = 0.0;
  for (std::size_t k = 0; k < 3; ++k) {
    const double d = static_cast<double>(a[k]) - static_cast<double>(b[k]);
    s += d * d;
  }
  return std::sqrt(s) / 255.0;
}

/// Mean colour error of a coloured model: the mean over the points p_i of color_distance(colors_i, ground-truth
/// colour at the surface point nearest to p_i) (surface_color on MeshDistance::closest). `truth.mesh()` must have
/// colours; `points` and `colors` must be non-empty and of equal size. Throws InvalidArgument otherwise or for a
/// non-finite point. Independent of `threads` (0 = hardware concurrency).
[[nodiscard]] inline double mean_color_error(const MeshDistance& truth, std::span<const Vec3> points,
                                             std::span<const Rgb> colors, unsigned threads = 0) {
  detail::require(!truth.mesh().colors.empty(), "mean_color_error: the ground-truth mesh has no colours");
  detail::require(!points.empty(), "mean_color_error: the model has no points");
  detail::require(colors.size() == points.size(), "mean_color_error: ", colors.size(), " colours for ",
                  points.size(), " points");
  for (std::size_t i = 0; i < points.size(); ++i) validate_finite(points[i], "mean_color_error point");
  std::vector<double> e(points.size());
  detail::parallel_for(points.size(), threads, [&](std::size_t b, std::size_t end) {
    for (std::size_t i = b; i < end; ++i) {
      const MeshDistance::Closest c = truth.closest(points[i]);
      e[i] = color_distance(colors[i], surface_color(truth.mesh(), c.triangle, c.point));
    }
  });
  double sum = 0.0;
  for (double x : e) sum += x;  // serial sum: the result does not depend on the thread count
  return sum / static_cast<double>(e.size());
}

/// mean_color_error of a model mesh's vertices and vertex colours (e.g. to_indexed_mesh of a coloured StreamingMesh).
[[nodiscard]] inline double mean_color_error(const MeshDistance& truth, const IndexedMesh& model, unsigned threads = 0) {
  detail::require(!model.colors.empty(), "mean_color_error: the model mesh has no colours");
  return mean_color_error(truth, model.vertices, model.colors, threads);
}

}  // namespace nbs
