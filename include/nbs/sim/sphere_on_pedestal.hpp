// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// A core-only scan simulator (no Embree): exact ray casts against an analytic object, the sensor's working range
/// and its Eq. (4.39) noise along the ray (CounterGaussian, addressed by seed, profile and ray, so a scan does not
/// depend on evaluation order). `SphereOnPedestal` models ScanSimulator; `scan_analytic` scans any object given by
/// its first-hit function. Used by example 06 and the tests.

#include <cmath>
#include <cstdint>
#include <optional>

#include "nbs/core/scan.hpp"
#include "nbs/core/scan_path.hpp"
#include "nbs/sensor/counter_gaussian.hpp"
#include "nbs/sensor/laser_stripe_profiler.hpp"

namespace nbs {

/// A sphere standing on the pedestal (touching z = 0 with the defaults), scanned by exact ray casts; models
/// ScanSimulator with a LaserStripeProfiler. Metres, world frame.
struct SphereOnPedestal {
  Vec3 center = Vec3(0.0, 0.0, 0.04);
  double radius_m = 0.04;

  /// Distance along unit d from o to the first hit (sphere, or the pedestal half-space z < 0), if any.
  [[nodiscard]] std::optional<double> hit(const Vec3& o, const Vec3& d, bool& on_sphere) const {
    std::optional<double> best;
    on_sphere = false;
    const Vec3 oc = o - center;
    const double b = oc.dot(d), c = oc.squaredNorm() - radius_m * radius_m, disc = b * b - c;
    if (disc >= 0.0) {
      const double t = -b - std::sqrt(disc);
      if (t > 0.0) best = t, on_sphere = true;
    }
    if (d.z() < 0.0 && o.z() > 0.0) {  // pedestal top z = 0 blocks the view and returns nothing
      const double t = -o.z() / d.z();
      if (!best || t < *best) best = t, on_sphere = false;
    }
    return best;
  }

  /// The bounding box of the object.
  [[nodiscard]] Aabb bounds() const {
    return {center - Vec3::Constant(radius_m), center + Vec3::Constant(radius_m)};
  }
  /// A bounding box of the unknown area for a planner: the object's box grown by `margin_m` sideways and upwards,
  /// from the pedestal plane z = 0.
  [[nodiscard]] Aabb unknown_area(double margin_m = 0.02) const {
    const Aabb b = bounds();
    return {Vec3(b.min.x() - margin_m, b.min.y() - margin_m, 0.0), b.max + Vec3::Constant(margin_m)};
  }

  [[nodiscard]] Scan scan(const LinearScanPath& path, const LaserStripeProfiler& lsp, std::uint64_t seed) const;
};

/// A scan of an analytic object: `hit(o, d, on_object)` returns the distance along unit d from o to the first hit
/// (setting on_object when it is the object, not the pedestal); points on the object within the sensor's range,
/// with its noise along the ray (CounterGaussian by seed, profile and ray).
template <class Hit>
[[nodiscard]] Scan scan_analytic(const Hit& hit, const LinearScanPath& path, const LaserStripeProfiler& lsp,
                                 std::uint64_t seed) {
  lsp.validate();
  Scan out;
  out.profile_poses = lsp.profile_poses(path);
  const CounterGaussian gauss(seed);
  for (std::size_t k = 0; k < out.profile_poses.size(); ++k) {
    const Pose& pose = out.profile_poses[k];
    for (int i = 0; i < lsp.points_per_profile; ++i) {
      ++out.rays_cast;
      const Vec3 d = pose.linear() * lsp.ray_direction_sensor(i);
      bool on_object = false;
      const std::optional<double> t = hit(pose.translation(), d, on_object);
      if (!t || !on_object || !lsp.range.contains(*t)) continue;
      const double noisy = *t + lsp.noise.sigma_m(*t) * gauss(k, static_cast<std::uint64_t>(i));
      out.add_point(pose.translation() + noisy * d, static_cast<std::uint32_t>(k));
    }
  }
  return out;
}

inline Scan SphereOnPedestal::scan(const LinearScanPath& path, const LaserStripeProfiler& lsp,
                                   std::uint64_t seed) const {
  return scan_analytic([this](const Vec3& o, const Vec3& d, bool& on) { return hit(o, d, on); }, path, lsp, seed);
}

}  // namespace nbs
