// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Viewpoint calculation along the quadratic patch (Sec. 4.3.1, Tab. 4.2, Eqs. 4.13–4.18), in the last sensor
/// frame S (patch frame).

#include <cmath>
#include <optional>

#include "nbs/candidates/detail/boundary_region.hpp"

namespace nbs::detail {

/// A candidate frame in S: axes (right-handed), position s_p, surface point p and the patch coordinate u.
struct PatchView {
  Vec3 s_x, s_y, s_z, s_p, p;
  double u = 0.0;
};

/// Inputs of the walk along the patch. Coordinates in S, metres.
struct PatchWalk {
  const QuadraticPatch* patch = nullptr;
  BoundaryAxes axes;
  Vec3 c_b = Vec3::Zero();        ///< boundary centre vertex in S
  Vec3 d_b = Vec3::Zero();        ///< boundary direction, unit, in S (Eq. 4.15)
  double standoff_m = 0.3;        ///< d_s
  double baseline_m = 0.1;        ///< l_b of Eq. 4.14 at d_s
  double step_m = 0.001;          ///< Δp of Tab. 4.2
  double overlap = 0.3;           ///< o wanted
  double max_step_angle_rad = 0.17;

  /// Patch point at trend coordinate u (the along coordinate stays that of c_b; Tab. 4.2).
  [[nodiscard]] Vec3 point(double u) const {
    Eigen::Vector2d xy;
    xy[axes.trend] = u;
    xy[axes.along] = c_b[axes.along];
    return patch->point(xy.x(), xy.y());
  }

  /// Eqs. 4.13, 4.15–4.18 at u; nullopt if d_b is parallel to the viewing direction. s_y is d_b made orthogonal
  /// to s_z and s_x = s_y × s_z: Eqs. 4.16–4.17 as printed give a left-handed frame in our right-handed convention
  /// (they were written for an SCS with x to the left); the axes agree up to the sign of s_x.
  [[nodiscard]] std::optional<PatchView> view(double u) const {
    PatchView v;
    v.u = u;
    v.p = point(u);
    Eigen::Vector2d xy;
    xy[axes.trend] = u;
    xy[axes.along] = c_b[axes.along];
    v.s_z = -patch->normal(xy.x(), xy.y()).normalized();  // inverse of n_i, Eq. 4.13
    Vec3 y = d_b - d_b.dot(v.s_z) * v.s_z;
    if (!(y.norm() > 1e-6) || !v.s_z.allFinite()) return std::nullopt;
    v.s_y = y.normalized();
    v.s_x = v.s_y.cross(v.s_z);
    v.s_p = v.p - standoff_m * v.s_z;  // Eq. 4.18
    return v;
  }

  /// o of Eq. 4.14 for view v: the part of the baseline (width l_b across s_x at distance d_s) that lies on the
  /// known side of the ray through c_b. Known side = against the step direction.
  [[nodiscard]] double overlap_of(const PatchView& v) const {
    const Vec3 rel = c_b - v.s_p;
    const double z = rel.dot(v.s_z);
    if (!(z > 0.0)) return 0.0;
    const double xc = standoff_m * rel.dot(v.s_x) / z;
    Vec3 step = Vec3::Zero();
    step[axes.trend] = axes.sign;
    const double sgn = step.dot(v.s_x) >= 0.0 ? 1.0 : -1.0;
    return std::clamp(sgn * xc + 0.5 * baseline_m, 0.0, baseline_m) / baseline_m;
  }
};

/// Steps u = u_0 + sign·k·Δp from c_b (Tab. 4.2) until o ≤ wanted (then bisects to o = wanted), the angle between
/// consecutive viewing directions exceeds the limit, or k·Δp > l_b; returns the last admissible view.
[[nodiscard]] inline std::optional<PatchView> walk_patch(const PatchWalk& w) {
  const double u0 = w.c_b[w.axes.trend];
  auto prev = w.view(u0);
  if (!prev) return std::nullopt;
  if (w.overlap_of(*prev) <= w.overlap) return prev;
  const int steps = static_cast<int>(std::ceil(w.baseline_m / w.step_m)) + 1;
  for (int k = 1; k <= steps; ++k) {
    auto cur = w.view(u0 + w.axes.sign * k * w.step_m);
    if (!cur || std::acos(std::clamp(cur->s_z.dot(prev->s_z), -1.0, 1.0)) > w.max_step_angle_rad) return prev;
    if (w.overlap_of(*cur) <= w.overlap) {
      double lo = prev->u, hi = cur->u;  // o(lo) > wanted ≥ o(hi)
      for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (lo + hi);
        const auto m = w.view(mid);
        if (!m) break;
        (w.overlap_of(*m) > w.overlap ? lo : hi) = mid;
      }
      auto v = w.view(hi);
      return v ? v : cur;
    }
    prev = cur;
  }
  return prev;
}

}  // namespace nbs::detail
