// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Synthetic recognition scenes: the bundled bunny, analytic shapes of its size, and partial views of a mesh at a
// seeded random pose.

#include <cmath>
#include <numbers>
#include <random>

#include "nbs/core/detail/random.hpp"
#include "nbs/io/load_mesh.hpp"
#include "nbs/mesh/indexed_mesh.hpp"
#include "nbs/mesh/normalize.hpp"
#include "nbs/recognition/oriented_points.hpp"
#include "nbs/sim/surface_samples.hpp"
#include "../sim/test_meshes.hpp"

namespace nbs::test {

/// The bundled Stanford bunny scaled to 0.16 m on the pedestal (as the demo).
inline IndexedMesh bunny() {
  IndexedMesh m = load_mesh(NBS_DATA_DIR "/meshes/stanford-bunny.obj");
  normalize_on_pedestal(m, 0.16, UpAxis::y);
  return m;
}

inline std::pair<Vec3, Vec3> bounds(const IndexedMesh& m) {
  Vec3 lo = m.vertices.front(), hi = lo;
  for (const Vec3& v : m.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  return {lo, hi};
}
/// The axis-aligned box of a mesh.
inline IndexedMesh box_like_bunny(const IndexedMesh& m) {
  const auto [lo, hi] = bounds(m);
  return box_mesh(lo, hi);
}
/// A sphere of the mesh's mean extent around its box centre.
inline IndexedMesh sphere_like_bunny(const IndexedMesh& m) {
  const auto [lo, hi] = bounds(m);
  return uv_sphere(0.5 * (lo + hi), (hi - lo).mean() / 2, 24, 48);
}

struct PartialView {
  OrientedPoints scene;  ///< scene frame
  Pose truth;            ///< T_SM
};

/// Samples of `m` (seed + 1000) whose normal faces a random view direction (n · v > 0.1: back faces culled, no
/// self-occlusion), moved by a random rotation and a translation in a 0.5 m box, with 0.5 mm Gaussian position noise
/// and about 2° of normal noise.
inline PartialView partial_view(const IndexedMesh& m, std::uint64_t seed, std::size_t samples = 20000) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  // One draw per statement (the order of draws within one expression is unspecified; gcc and clang differ), in
  // the order gcc 12 drew the former one-expression form, so that a seed gives the data the recognition tests'
  // bounds were set on: each vector z, y, x; the rotation axis, its angle, then the translation.
  const auto gauss3 = [&] {
    const double z = g(rng), y = g(rng), x = g(rng);
    return Vec3(x, y, z);
  };
  const Vec3 view = gauss3().normalized();
  const Vec3 axis = gauss3().normalized();
  const double angle = std::numbers::pi * detail::uniform01(rng);
  const double tz = detail::uniform01(rng), ty = detail::uniform01(rng), tx = detail::uniform01(rng);
  PartialView out;
  out.truth = Eigen::Translation3d(0.5 * Vec3(tx, ty, tz)) * Eigen::AngleAxisd(angle, axis);
  const SurfaceSamples s = sample_surface(m, samples, seed + 1000);
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s.normals[i].dot(view) <= 0.1) continue;
    out.scene.points.push_back(out.truth * s.points[i] + 0.0005 * gauss3());
    out.scene.normals.push_back((out.truth.linear() * s.normals[i] + 0.02 * gauss3()).normalized());
  }
  return out;
}

}  // namespace nbs::test
