// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// One linearised point-to-plane least-squares step (6 DoF) with the scaled normal matrix whose condition the ICP
/// checks (Sec. 3.2.3).

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <cmath>
#include <vector>

#include "nbs/core/types.hpp"

namespace nbs::detail {

/// A correspondence under the current estimate: scan point q (world, moved by the estimate), model normal n (unit)
/// and the signed point-to-plane residual r = n·(q − m), metres.
struct PlaneCorrespondence {
  Vec3 q;
  Vec3 n;
  double r;
};

/// The result of point_to_plane_step.
struct PointToPlaneStep {
  Pose update = Pose::Identity();  ///< world → world increment: x ↦ R(ω)(x − c) + c + t
  double condition = 0.0;          ///< λ_min / λ_max of the scaled 6×6 normal matrix (1 = isotropic, 0 = singular)
  double rms_m = 0.0;              ///< RMS of the residuals r
};

/// Minimises Σ (r + ((q − c)×n)·ω + n·t)² over (ω, t), linearised about the centroid c of the q. The rotation
/// unknowns are scaled by the RMS distance L of the q from c (unknowns L·ω and t, both metres), so that the
/// condition compares rotation and translation on the scale of the correspondences. `update` is the exact rigid
/// motion of the solution; it is identity when the system is singular (condition 0). `c` must not be empty.
template <class = void>  // lazy: instantiated where called, not where included (docs/robustness.md)
[[nodiscard]] inline PointToPlaneStep point_to_plane_step(const std::vector<PlaneCorrespondence>& c) {
  using Mat6 = Eigen::Matrix<double, 6, 6>;
  using Vec6 = Eigen::Matrix<double, 6, 1>;
  PointToPlaneStep out;
  const double count = static_cast<double>(c.size());
  Vec3 centroid = Vec3::Zero();
  double r2 = 0.0;
  for (const PlaneCorrespondence& k : c) centroid += k.q, r2 += k.r * k.r;
  centroid /= count;
  out.rms_m = std::sqrt(r2 / count);
  double spread2 = 0.0;
  for (const PlaneCorrespondence& k : c) spread2 += (k.q - centroid).squaredNorm();
  const double length = std::sqrt(spread2 / count);
  if (!(length > 0.0)) return out;
  Mat6 a = Mat6::Zero();
  Vec6 g = Vec6::Zero();
  for (const PlaneCorrespondence& k : c) {
    Vec6 j;
    j.head<3>() = (k.q - centroid).cross(k.n) / length;
    j.tail<3>() = k.n;
    a.selfadjointView<Eigen::Lower>().rankUpdate(j);
    g.noalias() -= k.r * j;
  }
  const Mat6 full = a.selfadjointView<Eigen::Lower>();
  const Eigen::SelfAdjointEigenSolver<Mat6> eig(full, Eigen::EigenvaluesOnly);
  const double lmax = eig.eigenvalues()[5], lmin = eig.eigenvalues()[0];
  out.condition = lmax > 0.0 ? std::max(0.0, lmin / lmax) : 0.0;
  if (!(out.condition > 0.0)) return out;
  const Vec6 x = full.ldlt().solve(g);
  const Vec3 omega = x.head<3>() / length;
  const double angle = omega.norm();
  const Mat3 rot = angle > 0.0 ? Mat3(Eigen::AngleAxisd(angle, omega / angle)) : Mat3::Identity();
  out.update.linear() = rot;
  out.update.translation() = centroid + x.tail<3>() - rot * centroid;
  return out;
}

}  // namespace nbs::detail
