// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Planarity of a boundary region from its surface normals (Sec. 4.3.1, Eqs. 4.19–4.21).
///
/// Reading: the text says that for a planar surface "λ1 would be one and the other eigenvalues zero" and tests
/// λ2, λ3 ≤ 0.09. That holds for the second-moment matrix M = (1/k) Σ n_i n_iᵀ of the unit normals (trace 1), not
/// for the mean-free C_N of Eq. 4.20 (all eigenvalues 0 for a plane; and a cylinder, whose normals spread in one
/// plane only, would have λ2 = λ3 ≈ 0 and count as planar). We therefore use M: its λ2, λ3 are the spread of the
/// normals across the mean normal n̄ of Eq. 4.19 (M = C_N + n̄ n̄ᵀ).

#include <Eigen/Eigenvalues>

#include <span>

#include "nbs/core/types.hpp"

namespace nbs::detail {

/// Eigenvalues λ1 ≥ λ2 ≥ λ3 of M = (1/k) Σ n̂_i n̂_iᵀ over the non-zero `normals` (normalised first); λ1 + λ2 + λ3 = 1.
/// Zero vector if no normal is non-zero.
[[nodiscard]] inline Vec3 normal_eigenvalues(std::span<const Vec3> normals) {
  Mat3 m = Mat3::Zero();
  std::size_t k = 0;
  for (const Vec3& n : normals) {
    const double len = n.norm();
    if (!(len > 0.0) || !std::isfinite(len)) continue;
    const Vec3 u = n / len;
    m += u * u.transpose();
    ++k;
  }
  if (k == 0) return Vec3::Zero();
  m /= static_cast<double>(k);
  const Eigen::SelfAdjointEigenSolver<Mat3> es(m, Eigen::EigenvaluesOnly);
  const Vec3 ascending = es.eigenvalues();
  return {ascending[2], ascending[1], ascending[0]};
}

/// Planar region (Sec. 4.3.1): at least one normal and λ2 ≤ limit and λ3 ≤ limit.
[[nodiscard]] inline bool normals_planar(std::span<const Vec3> normals, double limit) {
  const Vec3 l = normal_eigenvalues(normals);
  return l[0] > 0.0 && l[1] <= limit && l[2] <= limit;
}

}  // namespace nbs::detail
