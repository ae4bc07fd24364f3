// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Seeded area-uniform samples of a ground-truth surface, each flagged "bottom" if the pedestal hides it
/// (the ground-truth vertex set of the completeness measure, Sec. 4.7.2 / Tab. 5.2).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <vector>

#include "nbs/mesh/indexed_mesh.hpp"
#include "nbs/core/detail/random.hpp"

namespace nbs {

/// Which samples count as the object's bottom: the part that rests on the pedestal and cannot be scanned.
/// A sample is bottom iff z ≤ pedestal_z_m + band_m and its face is near-horizontal, |n_z| ≥ cos(max_tilt_rad).
/// The test uses |n_z| (not n_z < 0) because loaded meshes are not reliably oriented; an upward-facing horizontal
/// face within the band would be hidden by the pedestal just as well for bands of a millimetre.
struct BottomRule {
  double pedestal_z_m = 0.0;                        ///< height of the pedestal top (world z), metres.
  double band_m = 0.001;                            ///< height band above the pedestal, metres (≥ 0).
  double max_tilt_rad = std::numbers::pi / 4.0;     ///< largest angle between the face normal and ±z, [0, π/2].

  void validate() const {
    detail::require(std::isfinite(pedestal_z_m), "BottomRule::pedestal_z_m must be finite, got ", pedestal_z_m);
    detail::require_non_negative("BottomRule::band_m", band_m);
    detail::require_in_range("BottomRule::max_tilt_rad", max_tilt_rad, 0.0, std::numbers::pi / 2.0);
  }
  /// True if a sample at `p` on a face with unit normal `n` is bottom.
  [[nodiscard]] bool is_bottom(const Vec3& p, const Vec3& n) const {
    return p.z() <= pedestal_z_m + band_m && std::abs(n.z()) >= std::cos(max_tilt_rad);
  }
};

/// Samples of a surface, index-aligned. World frame, metres.
struct SurfaceSamples {
  std::vector<Vec3> points;              ///< sample positions on the surface.
  std::vector<Vec3> normals;             ///< unit face normal of the sampled triangle (orientation as stored).
  std::vector<std::uint32_t> triangle;   ///< index of the sampled triangle.
  std::vector<bool> bottom;              ///< true if the pedestal hides the sample (see BottomRule).

  [[nodiscard]] std::size_t size() const { return points.size(); }
  /// Number of samples that are not bottom (the denominator of c_a).
  [[nodiscard]] std::size_t non_bottom_count() const {
    return static_cast<std::size_t>(std::count(bottom.begin(), bottom.end(), false));
  }
};

/// `count` samples drawn i.i.d. with density proportional to area: a triangle is chosen with probability
/// area / total area, then a point uniformly inside it (u = 1 − √r₁, v = √r₁ (1 − r₂)). Zero-area triangles are
/// never chosen. Same mesh + count + seed ⇒ identical samples on every platform (std::mt19937_64, own
/// conversions). Throws InvalidArgument if the mesh is invalid (see IndexedMesh::validate), count == 0 or the rule
/// is invalid.
[[nodiscard]] inline SurfaceSamples sample_surface(const IndexedMesh& mesh, std::size_t count, std::uint64_t seed,
                                                   const BottomRule& rule = {}) {
  mesh.validate();
  rule.validate();
  detail::require(count > 0, "sample_surface: count must be > 0");
  std::vector<double> cumulative(mesh.triangles.size());
  double total = 0.0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) cumulative[t] = total += mesh.triangle_area(t);
  detail::require(std::isfinite(total) && total > 0.0, "sample_surface: mesh area is ", total);

  SurfaceSamples s;
  s.points.reserve(count);
  s.normals.reserve(count);
  s.triangle.reserve(count);
  s.bottom.reserve(count);
  std::mt19937_64 rng(seed);
  for (std::size_t i = 0; i < count; ++i) {
    const double target = detail::uniform01(rng) * total;
    // First triangle whose cumulative area exceeds target: never a zero-area one (its cumulative equals its
    // predecessor's, which is ≤ target).
    auto it = std::upper_bound(cumulative.begin(), cumulative.end(), target);
    if (it == cumulative.end()) --it;
    while (it != cumulative.begin() && mesh.triangle_area(static_cast<std::size_t>(it - cumulative.begin())) == 0.0)
      --it;
    const auto t = static_cast<std::size_t>(it - cumulative.begin());
    const double r1 = std::sqrt(detail::uniform01(rng));
    const double r2 = detail::uniform01(rng);
    const Vec3& a = mesh.corner(t, 0);
    const Vec3& b = mesh.corner(t, 1);
    const Vec3& c = mesh.corner(t, 2);
    const Vec3 p = (1.0 - r1) * a + r1 * (1.0 - r2) * b + r1 * r2 * c;
    const Vec3 n = mesh.face_normal_scaled(t).normalized();
    s.points.push_back(p);
    s.normals.push_back(n);
    s.triangle.push_back(static_cast<std::uint32_t>(t));
    s.bottom.push_back(rule.is_bottom(p, n));
  }
  return s;
}

/// Samples with `density_per_m2` samples per square metre of surface (count = ⌈area · density⌉, at least 1).
/// Throws InvalidArgument if the density is not finite and > 0, or as `sample_surface`.
[[nodiscard]] inline SurfaceSamples sample_surface_density(const IndexedMesh& mesh, double density_per_m2,
                                                           std::uint64_t seed, const BottomRule& rule = {}) {
  detail::require_positive("sample_surface_density: density_per_m2", density_per_m2);
  mesh.validate();
  const double n = std::ceil(mesh.area() * density_per_m2);
  detail::require(n <= 1e9, "sample_surface_density: ", n, " samples requested (more than 1e9)");
  return sample_surface(mesh, std::max<std::size_t>(1, static_cast<std::size_t>(n)), seed, rule);
}

}  // namespace nbs
