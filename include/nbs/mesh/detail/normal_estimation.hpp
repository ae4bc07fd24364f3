#pragma once
/// \file
/// Weighted PCA normal estimation over a ball neighbourhood (Sec. 3.3.1, "normal estimation" stage).

#include <Eigen/Eigenvalues>

#include <cmath>
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
};

/// Weighted PCA normal at `centre` from `points` (all within `radius_m`, the centre may be among them).
/// Weights w = 1 − (d / radius)², so near points dominate. The normal is flipped so that normal · line_of_sight < 0
/// (it points back to the sensor). Non-robust when a threshold of `rb` fails or the line of sight is (almost)
/// parallel to the tangent plane (|cos| < 0.02).
[[nodiscard]] inline NormalEstimate estimate_normal(const Vec3& centre, std::span<const Vec3> points,
                                                    double radius_m, const Vec3& line_of_sight,
                                                    const NormalRobustness& rb) {
  NormalEstimate out;
  if (static_cast<int>(points.size()) < rb.min_neighbours) return out;
  const double inv_r2 = 1.0 / (radius_m * radius_m);
  Vec3 mean = Vec3::Zero();
  double wsum = 0.0;
  for (const Vec3& p : points) {
    const double w = std::max(0.0, 1.0 - (p - centre).squaredNorm() * inv_r2) + 1e-6;
    mean += w * p;
    wsum += w;
  }
  mean /= wsum;
  Mat3 cov = Mat3::Zero();
  for (const Vec3& p : points) {
    const double w = std::max(0.0, 1.0 - (p - centre).squaredNorm() * inv_r2) + 1e-6;
    const Vec3 d = p - mean;
    cov.noalias() += w * d * d.transpose();
  }
  cov /= wsum;
  const Eigen::SelfAdjointEigenSolver<Mat3> es(cov);
  if (es.info() != Eigen::Success) return out;
  const Vec3 ev = es.eigenvalues();  // ascending
  if (!(ev(2) > 0.0) || ev(1) < rb.min_spread_ratio * ev(2) || ev(0) > rb.max_flatness_ratio * ev(1)) return out;
  Vec3 n = es.eigenvectors().col(0);
  const double c = n.dot(line_of_sight);
  if (!(std::abs(c) >= 0.02)) return out;
  out.normal = c > 0.0 ? Vec3(-n) : n;
  out.robust = out.normal.allFinite();
  return out;
}

}  // namespace nbs::detail
