// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// MeshDistance: exact unsigned distance from points to a triangle mesh surface, and the RMS error ē (Tab. 5.2).

#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

#include "nbs/mesh/indexed_mesh.hpp"
#include "nbs/core/detail/parallel_for.hpp"
#include "nbs/sim/detail/point_kd_tree.hpp"
#include "nbs/sim/point_triangle_distance.hpp"

namespace nbs {

/// Exact point-to-surface distance for an IndexedMesh (owns a copy). Metres.
///
/// Scheme: a kd-tree over triangle centroids c_t, and per triangle its bounding radius R_t = max |corner − c_t|.
/// For a query q, the triangle of the nearest centroid gives an upper bound U; any triangle closer than U satisfies
/// |q − c_t| − R_t < U, hence |q − c_t| < U + max R_t, so a radius search with that bound and exact
/// point-to-triangle tests over the candidates (skipping those with |q − c_t| − R_t ≥ best) is exact.
/// Thread-safety: const member functions may be called concurrently.
class MeshDistance {
public:
  /// Throws InvalidArgument if `mesh.validate()` fails (empty, non-finite, bad index, zero total area).
  explicit MeshDistance(const IndexedMesh& mesh) : mesh_((mesh.validate(), mesh)) {
    std::vector<Vec3> centroids(mesh_.triangles.size());
    radius_.resize(mesh_.triangles.size());
    for (std::size_t t = 0; t < mesh_.triangles.size(); ++t) {
      const Vec3 c = (mesh_.corner(t, 0) + mesh_.corner(t, 1) + mesh_.corner(t, 2)) / 3.0;
      centroids[t] = c;
      double r = 0.0;
      for (int k = 0; k < 3; ++k) r = std::max(r, (mesh_.corner(t, k) - c).norm());
      radius_[t] = r;
      max_radius_ = std::max(max_radius_, r);
    }
    tree_ = detail::PointKdTree(std::move(centroids));
  }

  [[nodiscard]] const IndexedMesh& mesh() const { return mesh_; }

  /// The nearest surface point of a query: its triangle, the point and its distance (metres).
  struct Closest {
    std::size_t triangle = 0;
    Vec3 point = Vec3::Zero();
    double distance = 0.0;
  };

  /// Exact nearest point to `q` on any triangle (ties: the triangle found first). Throws InvalidArgument if `q` is
  /// not finite.
  [[nodiscard]] Closest closest(const Vec3& q) const {
    validate_finite(q, "distance query point");
    const auto [t0, d2] = tree_.nearest(q);
    Closest best{t0, Vec3::Zero(), triangle_distance(q, t0)};
    // Slack covers the rounding of the centroid distances, so no candidate is lost to it.
    const double bound = best.distance + max_radius_ + 1e-9 * (best.distance + max_radius_ + std::sqrt(d2));
    tree_.for_each_within(q, bound, [&](std::size_t t, double dc2) {
      if (std::sqrt(dc2) - radius_[t] >= best.distance) return;
      const double d = triangle_distance(q, t);
      if (d < best.distance) best.triangle = t, best.distance = d;
    });
    best.point = closest_point_on_triangle(q, mesh_.corner(best.triangle, 0), mesh_.corner(best.triangle, 1),
                                           mesh_.corner(best.triangle, 2));
    return best;
  }

  /// Exact distance from `q` to the nearest point of any triangle. Throws InvalidArgument if `q` is not finite.
  [[nodiscard]] double distance(const Vec3& q) const { return closest(q).distance; }

  /// Distances of all points (index-aligned), computed on `threads` threads (0 = hardware concurrency).
  [[nodiscard]] std::vector<double> distances(std::span<const Vec3> points, unsigned threads = 0) const {
    for (std::size_t i = 0; i < points.size(); ++i) validate_finite(points[i], "distance query point");
    std::vector<double> out(points.size());
    detail::parallel_for(points.size(), threads, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) out[i] = distance(points[i]);
    });
    return out;
  }

  /// Coordinate root-mean-square error ē = sqrt(mean_i d(p_i)²) of model points to the surface (Tab. 5.2), metres.
  /// Throws InvalidArgument if `points` is empty or has a non-finite point. Independent of `threads`.
  [[nodiscard]] double rms_error(std::span<const Vec3> points, unsigned threads = 0) const {
    detail::require(!points.empty(), "rms_error: the model has no points");
    const std::vector<double> d = distances(points, threads);
    double sum = 0.0;
    for (double x : d) sum += x * x;  // serial sum: the result does not depend on the thread count
    return std::sqrt(sum / static_cast<double>(d.size()));
  }

private:
  [[nodiscard]] double triangle_distance(const Vec3& q, std::size_t t) const {
    return point_triangle_distance(q, mesh_.corner(t, 0), mesh_.corner(t, 1), mesh_.corner(t, 2));
  }

  IndexedMesh mesh_;
  std::vector<double> radius_;
  double max_radius_ = 0.0;
  detail::PointKdTree tree_;
};

}  // namespace nbs
