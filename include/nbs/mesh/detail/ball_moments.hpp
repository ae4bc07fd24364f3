// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// BallMoments: running weighted first and second moments of a pending StreamingMesh vertex's R_n ball, for an O(1)
/// "clearly not robust" verdict when the vertex is retried (see detail::clearly_not_robust). Lengths in metres,
/// relative to the vertex.

#include "nbs/core/types.hpp"

namespace nbs::detail {

/// Weighted moments of a pending vertex's points within R_n, relative to the vertex (centre included): Σw, Σw d,
/// Σw d dᵀ (lower triangle). Kept for every pending vertex (80 bytes) from its insertion until it is meshed, and
/// updated as points join its ball, so that a retry with a clearly non-robust neighbourhood costs O(1). One-pass,
/// so only good for a clear verdict (clearly_not_robust with a 1e-4 margin, which estimate() then agrees with).
struct BallMoments {
  double w = 0.0;
  Vec3 wd = Vec3::Zero();
  Mat3 wdd = Mat3::Zero();
  void add(const Vec3& d, double weight) {
    w += weight;
    wd += weight * d;
    for (int j = 0; j < 3; ++j)
      for (int i = j; i < 3; ++i) wdd(i, j) += weight * d(i) * d(j);
  }
  [[nodiscard]] Mat3 covariance() const {
    const Vec3 mean = wd / w;
    Mat3 c = Mat3::Zero();
    for (int j = 0; j < 3; ++j)
      for (int i = j; i < 3; ++i) c(i, j) = wdd(i, j) / w - mean(i) * mean(j);
    return c;
  }
};

}  // namespace nbs::detail
