// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Surface trend estimation: weighted least-squares quadratic patch, Eqs. (4.5)–(4.11), and its normal, Eq. (4.13).

#include <Eigen/QR>

#include <algorithm>
#include <optional>
#include <span>

#include "nbs/core/types.hpp"

namespace nbs {

/// Quadratic patch z = f(x, y) = a1 x² + a2 xy + a3 y² + a4 x + a5 y + a6 (Eq. 4.5) in a local frame whose +z is
/// the viewing direction of the sensor that saw the boundary (the sensor frame of the last scan, Sec. 4.2.2).
/// Coordinates in metres.
struct QuadraticPatch {
  Eigen::Matrix<double, 6, 1> a = Eigen::Matrix<double, 6, 1>::Zero();  ///< a1..a6 of Eq. 4.5.
  int rank = 0;  ///< 6: full quadric; 3: only the plane a4 x + a5 y + a6 was observable (a1 = a2 = a3 = 0).

  /// f(x, y), Eq. (4.5).
  [[nodiscard]] double z(double x, double y) const {
    return a[0] * x * x + a[1] * x * y + a[2] * y * y + a[3] * x + a[4] * y + a[5];
  }
  /// Surface point (x, y, f(x, y)).
  [[nodiscard]] Vec3 point(double x, double y) const { return {x, y, z(x, y)}; }
  /// Normal n = (∂f/∂x, ∂f/∂y, −1), Eq. (4.13): not normalised, pointing toward the sensor (−z).
  [[nodiscard]] Vec3 normal(double x, double y) const {
    return {2.0 * a[0] * x + a[1] * y + a[3], a[1] * x + 2.0 * a[2] * y + a[4], -1.0};
  }
};

/// Weight of a boundary-region vertex at distance `d` (m) from the nearest boundary vertex (Eq. 4.11).
/// Eq. 4.11 literally reads w = d, which contradicts the text ("vertices closer to the boundary are weighted
/// higher"); we implement the text: w = 1 for d ≤ `scale` (on or next to the boundary), decaying as scale / d.
[[nodiscard]] inline double boundary_distance_weight(double d, double scale) {
  detail::require_positive("boundary weight scale", scale);
  detail::require_non_negative("boundary distance", d);
  return d <= scale ? 1.0 : scale / d;
}

/// Weighted least-squares fit of Eq. (4.10), â = argmin Σ w_i (z_i − f(x_i, y_i))², solved by column-pivoting
/// Householder QR on W^{1/2} X (numerically equivalent to the SVD of the normal equations, better conditioned).
/// `points` are in the patch frame; `weights` (same size, each ≥ 0 and finite) are w_i of Eq. (4.11).
/// Coordinates are centred and scaled internally before solving. If the quadratic terms are unobservable (e.g. all
/// points on one line in x–y) falls back to a plane (rank 3); returns nullopt if not even a plane is determined.
/// Throws InvalidArgument on size mismatch, non-finite points or invalid weights.
template <class = void>  // lazy: instantiated where called, not where included (docs/robustness.md)
[[nodiscard]] inline std::optional<QuadraticPatch> fit_quadratic_patch(std::span<const Vec3> points,
                                                                       std::span<const double> weights) {
  detail::require(points.size() == weights.size(), "fit_quadratic_patch: ", points.size(), " points but ",
                  weights.size(), " weights");
  for (std::size_t i = 0; i < points.size(); ++i) {
    detail::require(points[i].allFinite(), "fit_quadratic_patch: point ", i, " is not finite");
    detail::require(std::isfinite(weights[i]) && weights[i] >= 0.0, "fit_quadratic_patch: weight ", i,
                    " must be finite and >= 0, got ", weights[i]);
  }
  if (points.size() < 3) return std::nullopt;
  // Centre and scale x, y so that the design matrix is well conditioned; undo analytically afterwards.
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  double wsum = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    c += weights[i] * points[i].head<2>();
    wsum += weights[i];
  }
  if (!(wsum > 0.0)) return std::nullopt;
  c /= wsum;
  double s = 0.0;
  for (const auto& p : points) s = std::max(s, (p.head<2>() - c).cwiseAbs().maxCoeff());
  if (!(s > 0.0)) return std::nullopt;

  const auto n = static_cast<Eigen::Index>(points.size());
  auto solve = [&](int cols) -> std::optional<Eigen::VectorXd> {
    Eigen::MatrixXd x(n, cols);
    Eigen::VectorXd z(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      const double sw = std::sqrt(weights[static_cast<std::size_t>(i)]);
      const Vec3& p = points[static_cast<std::size_t>(i)];
      const double u = (p.x() - c.x()) / s, v = (p.y() - c.y()) / s;
      if (cols == 6) x.row(i) << u * u, u * v, v * v, u, v, 1.0;  // Eq. 4.6
      else x.row(i) << u, v, 1.0;
      x.row(i) *= sw;
      z[i] = sw * p.z();  // Eq. 4.7
    }
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(x);
    qr.setThreshold(1e-9);
    if (qr.rank() < cols) return std::nullopt;
    return Eigen::VectorXd(qr.solve(z));
  };

  QuadraticPatch patch;
  Eigen::VectorXd b(6);
  if (auto q = solve(6)) {
    b = *q;
    patch.rank = 6;
  } else if (auto l = solve(3)) {
    b << 0, 0, 0, (*l)[0], (*l)[1], (*l)[2];
    patch.rank = 3;
  } else {
    return std::nullopt;
  }
  // f(x,y) = b1 u² + b2 uv + b3 v² + b4 u + b5 v + b6 with u = (x−cx)/s, v = (y−cy)/s: expand into a1..a6.
  const double s2 = s * s, cx = c.x(), cy = c.y();
  const double a1 = b[0] / s2, a2 = b[1] / s2, a3 = b[2] / s2;
  patch.a[0] = a1;
  patch.a[1] = a2;
  patch.a[2] = a3;
  patch.a[3] = -2.0 * a1 * cx - a2 * cy + b[3] / s;
  patch.a[4] = -a2 * cx - 2.0 * a3 * cy + b[4] / s;
  patch.a[5] = a1 * cx * cx + a2 * cx * cy + a3 * cy * cy - b[3] / s * cx - b[4] / s * cy + b[5];
  return patch;
}

}  // namespace nbs
