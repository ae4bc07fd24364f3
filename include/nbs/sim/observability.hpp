// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Observability ceiling c_obs: the share of non-bottom ground-truth samples that some admissible sensor position
/// can see at all, so that c_a / c_obs reads as "completeness of what can be seen".

#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "nbs/core/detail/parallel_for.hpp"
#include "nbs/sim/ray_caster.hpp"
#include "nbs/sim/surface_samples.hpp"

namespace nbs {

/// The oracle set of sensor positions and the admissibility rules. Angles in radians, lengths in metres.
///
/// For a sample p with unit normal n, the candidate sensor positions are s = p + d·u for every direction u of a
/// Fibonacci sphere with `directions` points plus ±n, and every distance d in the working range. s is admissible
/// if s_z > min_sensor_z_m (above the pedestal plane), the incidence angle ∠(u, ±n) ≤ incidence_cutoff_rad
/// (orientation-agnostic: |u·n| ≥ cos cutoff) and the segment s → p is unoccluded. Along one direction the segment
/// for d = min_range_m is contained in every longer one and has the highest sensor, so only d = min_range_m is
/// tested: the result is the same as for any dense set of distances in [min_range_m, max_range_m].
///
/// The ceiling is optimistic on purpose: it ignores the sensor body, robot reach, the triangulation baseline of a
/// real stripe profiler and the fan-angle limit; it does not ignore occlusion, range or incidence.
struct ObservabilitySettings {
  double min_range_m = 0.15;                                      ///< nearest admissible sensor distance (LSP).
  double max_range_m = 0.45;                                      ///< farthest admissible sensor distance (LSP).
  double incidence_cutoff_rad = 70.0 * std::numbers::pi / 180.0;  ///< Tab. 4.3 cut-off.
  double min_sensor_z_m = 0.0;                                    ///< sensor must be strictly above this height.
  int directions = 1000;                                          ///< Fibonacci-sphere directions per sample.
  double hit_tolerance_m = 1e-5;  ///< a first hit within this of the sample counts as the sample itself.
  unsigned threads = 0;           ///< worker threads (0 = hardware concurrency); results do not depend on it.

  void validate() const {
    detail::require_positive("ObservabilitySettings::min_range_m", min_range_m);
    detail::require(std::isfinite(max_range_m) && max_range_m >= min_range_m,
                    "ObservabilitySettings::max_range_m must be finite and >= min_range_m (", min_range_m, "), got ",
                    max_range_m);
    detail::require_in_range("ObservabilitySettings::incidence_cutoff_rad", incidence_cutoff_rad, 0.0,
                             std::numbers::pi / 2.0);
    detail::require(std::isfinite(min_sensor_z_m), "ObservabilitySettings::min_sensor_z_m must be finite, got ",
                    min_sensor_z_m);
    detail::require(directions >= 1, "ObservabilitySettings::directions must be >= 1, got ", directions);
    detail::require_positive("ObservabilitySettings::hit_tolerance_m", hit_tolerance_m);
  }
};

/// Per-sample observability and the ceiling c_obs.
struct Observability {
  std::vector<bool> observable;  ///< index-aligned with the samples; bottom samples are always false.
  std::size_t observable_count = 0;
  std::size_t non_bottom = 0;
  /// c_obs: observable share of the non-bottom samples (0 if there are none).
  [[nodiscard]] double c_obs() const { return non_bottom ? double(observable_count) / double(non_bottom) : 0.0; }
};

/// `n` unit directions of a Fibonacci sphere (deterministic, near-uniform).
[[nodiscard]] inline std::vector<Vec3> fibonacci_sphere(int n) {
  detail::require(n >= 1, "fibonacci_sphere: n must be >= 1, got ", n);
  std::vector<Vec3> d(static_cast<std::size_t>(n));
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / n;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    d[static_cast<std::size_t>(i)] = Vec3(r * std::cos(golden * i), r * std::sin(golden * i), z);
  }
  return d;
}

/// True if a sensor at `p + d·u` (d = min range) is admissible for the sample (p, n) and sees it.
template <RayCaster R>
[[nodiscard]] bool sees_sample(const R& caster, const Vec3& p, const Vec3& n, const Vec3& u,
                               const ObservabilitySettings& s) {
  if (std::abs(u.dot(n)) < std::cos(s.incidence_cutoff_rad)) return false;
  const Vec3 sensor = p + s.min_range_m * u;
  if (!(sensor.z() > s.min_sensor_z_m)) return false;
  const double dist = (p - sensor).norm();
  const Vec3 dir = (p - sensor) / dist;
  const auto hit = caster.first_hit(sensor, dir, dist - s.hit_tolerance_m);
  return !hit.has_value();
}

/// Computes which non-bottom samples are observable (see ObservabilitySettings). Deterministic; parallel over
/// samples. `caster` must cast against the same surface the samples were drawn from.
/// Throws InvalidArgument on invalid settings.
template <RayCaster R>
[[nodiscard]] Observability observability(const SurfaceSamples& samples, const R& caster,
                                          const ObservabilitySettings& settings = {}) {
  settings.validate();
  const std::vector<Vec3> dirs = fibonacci_sphere(settings.directions);
  std::vector<char> seen(samples.size(), 0);
  detail::parallel_for(samples.size(), settings.threads, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      if (samples.bottom[i]) continue;
      const Vec3& p = samples.points[i];
      const Vec3& n = samples.normals[i];
      bool ok = sees_sample(caster, p, n, n, settings) || sees_sample(caster, p, n, Vec3(-n), settings);
      for (std::size_t k = 0; !ok && k < dirs.size(); ++k) ok = sees_sample(caster, p, n, dirs[k], settings);
      seen[i] = ok ? 1 : 0;
    }
  });
  Observability o;
  o.observable.assign(seen.begin(), seen.end());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    o.non_bottom += samples.bottom[i] ? 0 : 1;
    o.observable_count += seen[i] ? 1 : 0;
  }
  return o;
}

}  // namespace nbs
