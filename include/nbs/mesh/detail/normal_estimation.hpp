// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Weighted PCA normal estimation over a ball neighbourhood (Sec. 3.3.1, "normal estimation" stage).

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <span>

#include "nbs/core/types.hpp"

namespace nbs::detail {

/// Robustness thresholds of a PCA normal. Eigenvalues λ0 ≤ λ1 ≤ λ2 of the weighted covariance.
struct NormalRobustness {
  int min_neighbours = 6;           ///< points in the R_n ball, the centre included.
  double min_spread_ratio = 0.05;   ///< λ1 / λ2 ≥ this: the neighbourhood is not collinear.
  double max_flatness_ratio = 0.5;  ///< λ0 / λ1 ≤ this: the neighbourhood is flat enough to have a tangent plane.
};

struct NormalEstimate {
  Vec3 normal = Vec3::Zero();  ///< unit, oriented against the line of sight; zero unless `robust`.
  bool robust = false;
  Vec3 mean = Vec3::Zero();    ///< weighted mean of the ball: a point of the PCA tangent plane.
};

/// Eigenvalues of the symmetric 3×3 matrix `a` (lower triangle read), ascending, in closed form (trigonometric
/// method). Accurate to about 1e-8 · λ2 (worst near a double eigenvalue); used only to reject clear cases early.
[[nodiscard]] inline Vec3 closed_form_eigenvalues(const Mat3& a) {
  const double p1 = a(1, 0) * a(1, 0) + a(2, 0) * a(2, 0) + a(2, 1) * a(2, 1);
  const double q = (a(0, 0) + a(1, 1) + a(2, 2)) / 3.0;
  const double b0 = a(0, 0) - q, b1 = a(1, 1) - q, b2 = a(2, 2) - q;
  const double p = std::sqrt((b0 * b0 + b1 * b1 + b2 * b2 + 2.0 * p1) / 6.0);
  if (!(p > 0.0)) return Vec3::Constant(q);
  // r = det((a − q I) / p) / 2, clamped to [−1, 1].
  const double det = b0 * (b1 * b2 - a(2, 1) * a(2, 1)) - a(1, 0) * (a(1, 0) * b2 - a(2, 1) * a(2, 0)) +
                     a(2, 0) * (a(1, 0) * a(2, 1) - b1 * a(2, 0));
  const double r = std::clamp(det / (2.0 * p * p * p), -1.0, 1.0);
  const double phi = std::acos(r) / 3.0;
  const double hi = q + 2.0 * p * std::cos(phi);
  const double lo = q + 2.0 * p * std::cos(phi + 2.0 * std::numbers::pi / 3.0);
  return {lo, 3.0 * q - hi - lo, hi};
}

/// True if the eigenvalues of the covariance `cov` (lower triangle read) fail a spread or flatness threshold of `rb`
/// by more than `margin` · λ2 (closed form; a margin well above its error, 1e-8 λ2, makes this agree with the solver).
[[nodiscard]] inline bool clearly_not_robust(const Mat3& cov, const NormalRobustness& rb, double margin) {
  const Vec3 cf = closed_form_eigenvalues(cov);
  const double m = margin * std::abs(cf(2));
  return cf(2) > 0.0 && (cf(1) < rb.min_spread_ratio * cf(2) - m || cf(0) > rb.max_flatness_ratio * cf(1) + m);
}

/// PCA weight w = 1 − (d / R_n)² (clamped at 0) + 1e-6 of a point at squared distance `d2` from the centre.
[[nodiscard]] inline double pca_weight(double d2, double inv_radius2) {
  return std::max(0.0, 1.0 - d2 * inv_radius2) + 1e-6;
}

/// Weighted PCA normal from `points` with weights `weights` (pca_weight() of their distance to the centre, so near
/// points dominate). The normal is flipped so that normal · line_of_sight < 0 (it points back to the sensor).
/// Non-robust when a threshold of `rb` fails or the line of sight is (almost) parallel to the tangent plane
/// (|cos| < 0.02).
[[nodiscard]] inline NormalEstimate estimate_normal(std::span<const Vec3> points, std::span<const double> weights,
                                                    const Vec3& line_of_sight, const NormalRobustness& rb) {
  NormalEstimate out;
  if (static_cast<int>(points.size()) < rb.min_neighbours) return out;
  Vec3 mean = Vec3::Zero();
  double wsum = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    mean += weights[i] * points[i];
    wsum += weights[i];
  }
  mean /= wsum;
  // Lower triangle only (all the solver reads), each entry the same sum of (w d_i) d_j as the full outer product.
  Mat3 cov = Mat3::Zero();
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3 d = points[i] - mean;
    const Vec3 wd = weights[i] * d;
    cov(0, 0) += wd.x() * d.x();
    cov(1, 0) += wd.y() * d.x();
    cov(2, 0) += wd.z() * d.x();
    cov(1, 1) += wd.y() * d.y();
    cov(2, 1) += wd.z() * d.y();
    cov(2, 2) += wd.z() * d.z();
  }
  for (int j = 0; j < 3; ++j)
    for (int i = j; i < 3; ++i) cov(i, j) /= wsum;
  // Clearly failing thresholds (beyond 1e-5 λ2, far above the closed form's error) are rejected without the
  // iterative solver; the verdict is the solver's one.
  if (clearly_not_robust(cov, rb, 1e-5)) return out;
  const Eigen::SelfAdjointEigenSolver<Mat3> es(cov);
  if (es.info() != Eigen::Success) return out;
  const Vec3 ev = es.eigenvalues();  // ascending
  if (!(ev(2) > 0.0) || ev(1) < rb.min_spread_ratio * ev(2) || ev(0) > rb.max_flatness_ratio * ev(1)) return out;
  Vec3 n = es.eigenvectors().col(0);
  const double c = n.dot(line_of_sight);
  if (!(std::abs(c) >= 0.02)) return out;
  out.normal = c > 0.0 ? Vec3(-n) : n;
  out.mean = mean;
  out.robust = out.normal.allFinite();
  return out;
}

}  // namespace nbs::detail
