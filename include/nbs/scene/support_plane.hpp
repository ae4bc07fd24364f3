// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Support-plane estimation: seeded RANSAC over the points, refined by least squares (PCA of the inliers).

#include <Eigen/Eigenvalues>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "nbs/core/detail/random.hpp"
#include "nbs/core/error.hpp"
#include "nbs/core/types.hpp"

namespace nbs::scene {

/// Plane n·p + d = 0 (world frame, metres), |n| = 1, n pointing up (n_z ≥ 0).
struct Plane {
  Vec3 normal = Vec3::UnitZ();
  double offset_m = 0.0;  ///< d.
  /// Signed distance of p, metres; positive above the plane (on the side n points to).
  [[nodiscard]] double signed_distance(const Vec3& p) const { return normal.dot(p) + offset_m; }
  /// z of the plane at (x, y); requires a non-vertical plane.
  [[nodiscard]] double z_at(double x, double y) const {
    return -(normal.x() * x + normal.y() * y + offset_m) / normal.z();
  }
};

/// Settings of fit_support_plane.
struct PlaneSettings {
  double distance_threshold_m = 0.005;  ///< inlier band: |signed distance| ≤ this.
  int iterations = 300;                 ///< RANSAC hypotheses (three points each).
  std::size_t min_inliers = 500;        ///< least inliers (of all points) of an accepted plane.
  double max_tilt_rad = 0.5;            ///< largest angle between the plane normal and world +z.
  std::size_t max_scored_points = 20000; ///< hypotheses are scored on an evenly strided subset of this size.
  std::uint64_t seed = 1;

  /// Throws InvalidArgument naming the first invalid value.
  void validate() const {
    detail::require_positive("PlaneSettings.distance_threshold_m", distance_threshold_m);
    detail::require(iterations > 0, "PlaneSettings.iterations must be > 0, got ", iterations);
    detail::require(min_inliers >= 3, "PlaneSettings.min_inliers must be >= 3, got ", min_inliers);
    detail::require(std::isfinite(max_tilt_rad) && max_tilt_rad > 0.0 && max_tilt_rad <= std::numbers::pi / 2,
                    "PlaneSettings.max_tilt_rad must be in (0, pi/2], got ", max_tilt_rad);
    detail::require(max_scored_points >= 3, "PlaneSettings.max_scored_points must be >= 3, got ", max_scored_points);
  }
};

/// Result of fit_support_plane. `found` false: no plane with min_inliers inliers within max_tilt_rad; `message` says
/// what was found instead.
struct PlaneFit {
  bool found = false;
  Plane plane;
  std::vector<std::size_t> inliers;  ///< indices into the input, ascending (of the refined plane).
  std::string message;
};

/// Throws InvalidArgument if `points` is empty or holds a non-finite point (naming its index).
inline void require_finite_cloud(std::span<const Vec3> points, const char* who) {
  detail::require(!points.empty(), who, ": the point cloud is empty");
  for (std::size_t i = 0; i < points.size(); ++i)
    detail::require(points[i].allFinite(), who, ": point ", i, " is not finite: (", points[i].transpose(), ")");
}

namespace impl {
/// Least-squares plane through `points[idx]` (normal = eigenvector of the smallest covariance eigenvalue), n_z ≥ 0.
[[nodiscard]] inline Plane fit_plane_pca(std::span<const Vec3> points, std::span<const std::size_t> idx) {
  Vec3 c = Vec3::Zero();
  for (auto i : idx) c += points[i];
  c /= static_cast<double>(idx.size());
  Mat3 cov = Mat3::Zero();
  for (auto i : idx) {
    const Vec3 d = points[i] - c;
    cov += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Mat3> es(cov);
  Vec3 n = es.eigenvectors().col(0).normalized();
  if (n.z() < 0.0) n = -n;
  return {n, -n.dot(c)};
}

[[nodiscard]] inline std::vector<std::size_t> plane_inliers(std::span<const Vec3> points, const Plane& p, double t) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (std::abs(p.signed_distance(points[i])) <= t) out.push_back(i);
  return out;
}
}  // namespace impl

/// The dominant near-horizontal plane of `points` (world frame, metres): RANSAC with `iterations` three-point
/// hypotheses drawn from std::mt19937_64(seed), scored on a strided subset; the best one's inliers (all points)
/// refined twice by PCA. Serial: the result depends on the seed only. Throws InvalidArgument for invalid settings,
/// an empty cloud or a non-finite point.
[[nodiscard]] inline PlaneFit fit_support_plane(std::span<const Vec3> points, const PlaneSettings& s) {
  s.validate();
  require_finite_cloud(points, "fit_support_plane");
  PlaneFit out;
  if (points.size() < 3) {
    out.message = detail::concat("no plane: ", points.size(), " points");
    return out;
  }
  const std::size_t stride = (points.size() + s.max_scored_points - 1) / s.max_scored_points;
  std::mt19937_64 rng(s.seed);
  const auto pick = [&] { return static_cast<std::size_t>(detail::uniform01(rng) * static_cast<double>(points.size())); };
  const double cos_tilt = std::cos(s.max_tilt_rad);
  std::size_t best_count = 0;
  Plane best;
  for (int it = 0; it < s.iterations; ++it) {
    const Vec3& a = points[pick()];
    const Vec3& b = points[pick()];
    const Vec3& c = points[pick()];
    Vec3 n = (b - a).cross(c - a);
    const double len = n.norm();
    if (!(len > 1e-12)) continue;  // degenerate sample
    n /= len;
    if (n.z() < 0.0) n = -n;
    if (n.z() < cos_tilt) continue;
    const Plane p{n, -n.dot(a)};
    std::size_t count = 0;
    for (std::size_t i = 0; i < points.size(); i += stride)
      count += std::abs(p.signed_distance(points[i])) <= s.distance_threshold_m ? 1 : 0;
    if (count > best_count) best_count = count, best = p;
  }
  if (best_count == 0) {
    out.message = detail::concat("no plane within max_tilt_rad ", s.max_tilt_rad, " among ", s.iterations,
                                 " RANSAC hypotheses");
    return out;
  }
  Plane plane = best;
  std::vector<std::size_t> in = impl::plane_inliers(points, plane, s.distance_threshold_m);
  for (int refine = 0; refine < 2 && in.size() >= 3; ++refine) {
    plane = impl::fit_plane_pca(points, in);
    in = impl::plane_inliers(points, plane, s.distance_threshold_m);
  }
  if (in.size() < s.min_inliers || plane.normal.z() < cos_tilt) {
    out.message = detail::concat("no plane: the best has ", in.size(), " inliers (min_inliers ", s.min_inliers,
                                 ") and tilt ", std::acos(std::min(1.0, plane.normal.z())), " rad");
    return out;
  }
  out.found = true;
  out.plane = plane;
  out.inliers = std::move(in);
  return out;
}

}  // namespace nbs::scene
