// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Euclidean (single-linkage) clustering of a point cloud with a kd-tree.

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/core/types.hpp"
#include "nbs/sim/detail/point_kd_tree.hpp"

namespace nbs::scene {

/// Settings of euclidean_clusters.
struct ClusterSettings {
  double tolerance_m = 0.01;         ///< two points closer than or at this distance belong to the same cluster.
  std::size_t min_size = 50;         ///< smaller clusters are dropped.
  std::size_t max_size = 1'000'000;  ///< larger clusters are dropped.

  /// Throws InvalidArgument naming the first invalid value.
  void validate() const {
    detail::require_positive("ClusterSettings.tolerance_m", tolerance_m);
    detail::require(min_size >= 1, "ClusterSettings.min_size must be >= 1, got ", min_size);
    detail::require(max_size >= min_size, "ClusterSettings.max_size must be >= min_size (", min_size, "), got ",
                    max_size);
  }
};

/// The connected components of the graph joining points at distance ≤ tolerance_m (single linkage), those with a
/// size in [min_size, max_size]. Each cluster lists point indices ascending; clusters are ordered by their smallest
/// index. Serial and deterministic. Throws InvalidArgument for invalid settings or a non-finite point (an empty
/// cloud gives no clusters).
[[nodiscard]] inline std::vector<std::vector<std::size_t>> euclidean_clusters(std::span<const Vec3> points,
                                                                               const ClusterSettings& s) {
  s.validate();
  for (std::size_t i = 0; i < points.size(); ++i)
    detail::require(points[i].allFinite(), "euclidean_clusters: point ", i, " is not finite: (",
                    points[i].transpose(), ")");
  std::vector<std::vector<std::size_t>> out;
  if (points.empty()) return out;
  const detail::PointKdTree tree(std::vector<Vec3>(points.begin(), points.end()));
  std::vector<char> seen(points.size(), 0);
  std::vector<std::size_t> cluster;
  for (std::size_t seed = 0; seed < points.size(); ++seed) {
    if (seen[seed]) continue;
    cluster.assign(1, seed);
    seen[seed] = 1;
    for (std::size_t head = 0; head < cluster.size(); ++head)
      tree.for_each_within(points[cluster[head]], s.tolerance_m, [&](std::size_t j, double) {
        if (!seen[j]) seen[j] = 1, cluster.push_back(j);
      });
    if (cluster.size() < s.min_size || cluster.size() > s.max_size) continue;
    std::sort(cluster.begin(), cluster.end());
    out.push_back(cluster);
  }
  return out;
}

}  // namespace nbs::scene
