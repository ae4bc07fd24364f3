// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Alg. 2 building blocks: fixed direction pattern, occlusion test in the voxel space, the 20 % selection rule.

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <vector>

#include "nbs/candidates/planning_context.hpp"

namespace nbs::detail {

/// Any unit vector orthogonal to unit `n`.
[[nodiscard]] inline Vec3 any_orthogonal(const Vec3& n) {
  const Vec3 a = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  return n.cross(a).normalized();
}

/// `count` unit directions on a Fibonacci (golden-angle) spiral around the pole `pole` (unit): over the
/// hemisphere ñ·pole > 0 if `hemisphere`, else over the whole sphere. A fixed pattern: no randomness.
[[nodiscard]] inline std::vector<Vec3> spiral_directions(const Vec3& pole, int count, bool hemisphere) {
  const Vec3 u = any_orthogonal(pole), v = pole.cross(u);
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  std::vector<Vec3> dirs;
  dirs.reserve(static_cast<std::size_t>(std::max(count, 0)));
  for (int i = 0; i < count; ++i) {
    const double f = (i + 0.5) / count;
    const double z = hemisphere ? 1.0 - f : 1.0 - 2.0 * f;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z)), phi = golden * i;
    dirs.push_back((z * pole + r * std::cos(phi) * u + r * std::sin(phi) * v).normalized());
  }
  return dirs;
}

/// isOcclusionFree of Alg. 2: the ray from `center` + offset·dir to `center` + d_s·dir meets no occupied voxel.
/// The first `offset_m` are skipped so that the surface voxels around the hole itself do not count.
template <VoxelSpace Space>
[[nodiscard]] bool occlusion_free(const Space& space, const Vec3& center, const Vec3& dir, double standoff_m,
                                  double offset_m) {
  const double from = std::min(offset_m, standoff_m);
  return !space.cast_ray(Ray{center + from * dir, center + standoff_m * dir}, ContinueVisit{}).hit;
}

/// The 20 % rule of Alg. 2: among the free samples, ordered by d_n = |n_h − ñ| (ties: sample order), the first whose
/// d_n ≥ d_front + 0.2 (d_back − d_front) (N_f.lower_bound). nullopt if none is free. Returns the sample index.
[[nodiscard]] inline std::optional<std::size_t> select_hole_normal(const Vec3& pca_normal,
                                                                   const std::vector<Vec3>& samples,
                                                                   const std::vector<char>& free,
                                                                   double fraction = 0.2) {
  std::vector<std::pair<double, std::size_t>> nf;  // N_f
  for (std::size_t i = 0; i < samples.size() && i < free.size(); ++i)
    if (free[i]) nf.emplace_back((pca_normal - samples[i]).norm(), i);
  if (nf.empty()) return std::nullopt;
  std::stable_sort(nf.begin(), nf.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  const double key = nf.front().first + fraction * (nf.back().first - nf.front().first);
  const auto it = std::lower_bound(nf.begin(), nf.end(), key, [](const auto& e, double k) { return e.first < k; });
  return (it == nf.end() ? nf.back() : *it).second;
}

}  // namespace nbs::detail
