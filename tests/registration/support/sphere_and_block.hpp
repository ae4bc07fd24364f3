// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A core-only analytic scanner for registration in the planner: the sphere of SphereOnPedestal
// (tests/planner/support/analytic_scanner.hpp) with a box standing next to it on the pedestal. The sphere alone is
// rotationally symmetric (ICP refuses it as degenerate); the box's faces fix the remaining rotations. Exact ray
// casts, the sensor's range and its noise along the ray (scan_analytic).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>

#include "nbs/core/scan.hpp"
#include "nbs/core/scan_path.hpp"
#include "nbs/sensor/laser_stripe_profiler.hpp"
#include "planner/support/analytic_scanner.hpp"

namespace nbs::test {

struct SphereAndBlock {
  SphereOnPedestal sphere{Vec3(-0.01, 0.01, 0.03), 0.03};
  Aabb block{Vec3(0.01, -0.045, 0.0), Vec3(0.045, -0.01, 0.045)};

  /// Distance along unit d from o to the box, if the ray enters it (slabs).
  [[nodiscard]] std::optional<double> block_hit(const Vec3& o, const Vec3& d) const {
    double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
      if (d[k] == 0.0) {
        if (o[k] < block.min[k] || o[k] > block.max[k]) return std::nullopt;
        continue;
      }
      double a = (block.min[k] - o[k]) / d[k], b = (block.max[k] - o[k]) / d[k];
      if (a > b) std::swap(a, b);
      t0 = std::max(t0, a), t1 = std::min(t1, b);
    }
    return t0 > 0.0 && t0 <= t1 ? std::optional<double>(t0) : std::nullopt;
  }

  /// Distance of p from the object's surface (sphere or box), metres.
  [[nodiscard]] double distance(const Vec3& p) const {
    const double ds = std::abs((p - sphere.center).norm() - sphere.radius_m);
    const Vec3 out = (block.min - p).cwiseMax(p - block.max).cwiseMax(Vec3::Zero());
    const double inside = std::min((p - block.min).minCoeff(), (block.max - p).minCoeff());
    const double db = out.norm() > 0.0 ? out.norm() : inside;
    return std::min(ds, db);
  }

  /// The first hit along unit d from o: the box, the sphere, or the pedestal (on_object false).
  [[nodiscard]] std::optional<double> hit(const Vec3& o, const Vec3& d, bool& on_object) const {
    std::optional<double> t = sphere.hit(o, d, on_object);
    if (const std::optional<double> tb = block_hit(o, d); tb && (!t || *tb < *t)) t = tb, on_object = true;
    return t;
  }

  [[nodiscard]] Scan scan(const LinearScanPath& path, const LaserStripeProfiler& lsp, std::uint64_t seed) const {
    return scan_analytic([this](const Vec3& o, const Vec3& d, bool& on) { return hit(o, d, on); }, path, lsp, seed);
  }
};

}  // namespace nbs::test
