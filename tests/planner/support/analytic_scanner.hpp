// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Core-only stand-in for the Embree scanner: exact ray casts against a sphere standing on the pedestal (z = 0),
// working range and Eq. (4.39)-style noise of the sensor along the ray (CounterGaussian, addressed by seed,
// profile and ray, so a scan does not depend on evaluation order). Models nbs::ScanSimulator.

#include <cmath>
#include <cstdint>
#include <optional>

#include "nbs/core/scan.hpp"
#include "nbs/core/scan_path.hpp"
#include "nbs/sensor/counter_gaussian.hpp"
#include "nbs/sensor/laser_stripe_profiler.hpp"
#include "nbs/sensor/presets.hpp"

namespace nbs::test {

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

/// The bounding box of the unknown area around SphereOnPedestal: pedestal plane z = 0 up to above the top.
inline Aabb sphere_box() { return {Vec3(-0.06, -0.06, 0.0), Vec3(0.06, 0.06, 0.10)}; }

/// A lighter LSP (fewer rays, 2 mm profile spacing) so that loop tests stay fast; geometry as the DLR LSP.
inline LaserStripeProfiler light_lsp(int points_per_profile = 200) {
  LaserStripeProfiler s = presets::dlr_lsp();
  s.points_per_profile = points_per_profile;
  s.profile_spacing_m = 0.002;
  return s;
}

}  // namespace nbs::test
