// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Per-point normals of a scan for the ICP's normal gate (Sec. 3.2.3): principal component analysis over the
/// ball neighbourhood in the scan itself, oriented towards the sensor.

#include <Eigen/Eigenvalues>

#include <cstddef>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/core/scan.hpp"
#include "nbs/core/types.hpp"
#include "nbs/sim/detail/point_kd_tree.hpp"

namespace nbs {

/// The rule of estimate_scan_normals.
struct ScanNormalSetting {
  double radius_m = 0.003;          ///< ball neighbourhood radius, metres
  std::size_t min_neighbours = 6;   ///< a point needs this many points (itself included) within radius_m
  double min_planarity = 0.05;      ///< and λ_mid / λ_max of their covariance ≥ this (not collinear, e.g. one profile)
};

/// Unit normal of every scan point (world frame), or zero for a point without one. Rule: the points of `scan`
/// within `s.radius_m` of point i (itself included, Euclidean, inclusive) give the covariance C (about their mean);
/// the normal is C's eigenvector of the smallest eigenvalue, flipped to point towards the sensor origin
/// `scan.origin(i)`. Point i gets no normal if it has fewer than `s.min_neighbours` such points or if
/// λ_mid < s.min_planarity·λ_max (neighbours on a line, e.g. a single stripe profile). O(n log n) with a kd-tree
/// over the scan; deterministic. Throws InvalidArgument for a radius that is not finite and > 0.
[[nodiscard]] inline std::vector<Vec3> estimate_scan_normals(const Scan& scan, const ScanNormalSetting& s) {
  detail::require_positive("scan normal radius_m", s.radius_m);
  const detail::PointKdTree tree(scan.points);
  std::vector<Vec3> normals(scan.size(), Vec3::Zero());
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const Vec3& p = scan.points[i];
    std::size_t count = 0;
    Vec3 sum = Vec3::Zero();
    Mat3 outer = Mat3::Zero();
    tree.for_each_within(p, s.radius_m, [&](std::size_t j, double) {
      const Vec3 d = scan.points[j] - p;  // relative to the query point: no cancellation for world coordinates
      ++count;
      sum += d;
      outer.noalias() += d * d.transpose();
    });
    if (count < s.min_neighbours) continue;
    const Vec3 mean = sum / static_cast<double>(count);
    const Mat3 cov = outer / static_cast<double>(count) - mean * mean.transpose();
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(cov);  // eigenvalues ascending
    const Vec3 lambda = eig.eigenvalues();
    if (!(lambda[2] > 0.0) || !(lambda[1] >= s.min_planarity * lambda[2])) continue;
    Vec3 n = eig.eigenvectors().col(0).normalized();
    if (n.dot(scan.origin(i) - p) < 0.0) n = -n;
    normals[i] = n;
  }
  return normals;
}

}  // namespace nbs
