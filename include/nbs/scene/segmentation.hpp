// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Table-top segmentation of an overview cloud: support plane (RANSAC + least squares), removal of the plane and of
/// what lies below it, Euclidean clustering of the rest; each cluster is an object hypothesis with the box that NBS
/// modeling of it starts from (the unknown area, standing on the plane).

#include <algorithm>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/core/types.hpp"
#include "nbs/scene/euclidean_clusters.hpp"
#include "nbs/scene/support_plane.hpp"

namespace nbs::scene {

/// Settings of segment_scene.
struct SegmentationSettings {
  PlaneSettings plane;
  ClusterSettings cluster;
  /// Points with signed distance ≤ this above the plane are removed with it (metres; default: the inlier band).
  double plane_clearance_m = 0.005;
  double box_margin_m = 0.01;  ///< the hypothesis box is grown by this in x, y and at its top (metres).

  /// Throws InvalidArgument naming the first invalid value.
  void validate() const {
    plane.validate();
    cluster.validate();
    detail::require_non_negative("SegmentationSettings.plane_clearance_m", plane_clearance_m);
    detail::require_non_negative("SegmentationSettings.box_margin_m", box_margin_m);
  }
};

/// One cluster above the support plane.
struct ObjectHypothesis {
  std::vector<std::size_t> indices;  ///< into the input cloud, ascending.
  std::vector<Vec3> points;          ///< the cluster's points (world frame).
  Vec3 centroid = Vec3::Zero();
  /// Axis-aligned box of the points, its bottom lowered to the plane (the lowest plane z under its corners), grown
  /// by box_margin_m in x, y and at the top: the unknown area for NBS modeling of this object.
  Aabb box;
};

enum class SegmentationStatus { ok, no_plane };

[[nodiscard]] inline std::string_view to_string(SegmentationStatus s) {
  return s == SegmentationStatus::ok ? "ok" : "no_plane";
}

struct Segmentation {
  SegmentationStatus status = SegmentationStatus::no_plane;
  std::string message;               ///< why no plane was found (status no_plane).
  PlaneFit plane;
  std::size_t removed_points = 0;    ///< on or below the plane.
  std::vector<ObjectHypothesis> objects;  ///< ordered by smallest point index.
};

/// The hypothesis of the cloud points `members` (indices into `points`, ascending, not empty): the points, their
/// centroid, and their box with its bottom lowered to `plane` under its corners and grown by s.box_margin_m in x, y
/// and at the top.
[[nodiscard]] inline ObjectHypothesis make_hypothesis(std::span<const Vec3> points, std::span<const std::size_t> members,
                                                      const Plane& plane, const SegmentationSettings& s) {
  detail::require(!members.empty(), "make_hypothesis: no member points");
  ObjectHypothesis h;
  for (const std::size_t i : members) {
    detail::require(i < points.size(), "make_hypothesis: member ", i, " is outside the cloud of ", points.size(),
                    " points");
    h.indices.push_back(i);
    h.points.push_back(points[i]);
    h.centroid += points[i];
    h.box.extend(points[i]);
  }
  h.centroid /= static_cast<double>(members.size());
  double bottom = h.box.min.z();
  for (double x : {h.box.min.x(), h.box.max.x()})
    for (double y : {h.box.min.y(), h.box.max.y()}) bottom = std::min(bottom, plane.z_at(x, y));
  h.box.min = Vec3(h.box.min.x() - s.box_margin_m, h.box.min.y() - s.box_margin_m, bottom);
  h.box.max += Vec3::Constant(s.box_margin_m);
  return h;
}

/// The Euclidean clusters (s.cluster) of `subset`, the cloud points points[index[j]] = subset[j], each as a
/// make_hypothesis of its cloud indices; ordered by smallest subset index.
[[nodiscard]] inline std::vector<ObjectHypothesis> cluster_hypotheses(std::span<const Vec3> points,
                                                                     std::span<const Vec3> subset,
                                                                     std::span<const std::size_t> index,
                                                                     const Plane& plane, const SegmentationSettings& s) {
  std::vector<ObjectHypothesis> out;
  for (const auto& cluster : euclidean_clusters(subset, s.cluster)) {
    std::vector<std::size_t> members;
    for (const std::size_t j : cluster) members.push_back(index[j]);
    out.push_back(make_hypothesis(points, members, plane, s));
  }
  return out;
}

/// The points of `h` (from the cloud `points`) that `keep` says to keep, clustered again (s.cluster: clusters below
/// min_size are dropped) into hypotheses by make_hypothesis — e.g. what a recognised object leaves of a cluster that
/// held it and a neighbour. `keep(k)` takes the index k into h.points. Ordered by smallest point index.
template <class Keep>
[[nodiscard]] std::vector<ObjectHypothesis> split_hypothesis(std::span<const Vec3> points, const ObjectHypothesis& h,
                                                             Keep&& keep, const Plane& plane,
                                                             const SegmentationSettings& s) {
  s.validate();
  std::vector<Vec3> rest;
  std::vector<std::size_t> index;
  for (std::size_t k = 0; k < h.points.size(); ++k)
    if (keep(k)) rest.push_back(h.points[k]), index.push_back(h.indices[k]);
  return cluster_hypotheses(points, rest, index, plane, s);
}

/// Segments `points` (world frame, metres). Deterministic for the settings' seed (serial). Throws InvalidArgument for
/// invalid settings, an empty cloud or a non-finite point; a cloud without a plane gives status no_plane.
[[nodiscard]] inline Segmentation segment_scene(std::span<const Vec3> points, const SegmentationSettings& s) {
  s.validate();
  Segmentation out;
  out.plane = fit_support_plane(points, s.plane);
  if (!out.plane.found) {
    out.message = out.plane.message;
    return out;
  }
  out.status = SegmentationStatus::ok;
  const Plane& plane = out.plane.plane;
  const double clearance = std::max(s.plane_clearance_m, s.plane.distance_threshold_m);
  std::vector<Vec3> above;
  std::vector<std::size_t> index;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (plane.signed_distance(points[i]) > clearance) above.push_back(points[i]), index.push_back(i);
  out.removed_points = points.size() - above.size();
  out.objects = cluster_hypotheses(points, above, index, plane, s);
  return out;
}

}  // namespace nbs::scene
