// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Alignment and merging of two models of one object made in two sessions (the object turned over in between,
/// thesis Sec. 5.3): a coarse global alignment by point-pair features (PpfModel over model a, match_ppf with model
/// b's points as the scene), each of the best hypotheses refined by the registration module's Icp, the one that
/// brings most of b's points onto a kept; then the union of the two meshes in a's frame.

#include <cmath>
#include <cstddef>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/core/scan.hpp"
#include "nbs/mesh/indexed_mesh.hpp"
#include "nbs/mesh/transformed_mesh.hpp"
#include "nbs/recognition/oriented_points.hpp"
#include "nbs/recognition/ppf_match.hpp"
#include "nbs/recognition/ppf_model.hpp"
#include "nbs/recognition/refine_pose.hpp"
#include "nbs/registration/icp.hpp"
#include "nbs/sim/detail/point_kd_tree.hpp"

namespace nbs {

/// Icp settings of align_models (see ModelAlignmentSetting::icp).
[[nodiscard]] inline IcpSetting alignment_icp_setting() {
  IcpSetting s = recognition_icp_setting();
  s.min_condition = 1e-4;
  return s;
}

/// Settings of align_models.
struct ModelAlignmentSetting {
  PpfModelSetting ppf{};     ///< the description of model a
  PpfMatchSetting match{};   ///< the voting of model b's points
  std::size_t refined_hypotheses = 3;  ///< the best PPF hypotheses each refined by ICP, ≥ 1
  /// The refinement: recognition_icp_setting() (10 mm radius, ≤ 30 iterations) with min_condition 1e-4 — whole
  /// models overlap in thousands of points, and a model made of planes (a box) has conditions near the default 3e-3.
  IcpSetting icp = alignment_icp_setting();
  double inlier_radius_m = 0.003;  ///< a point of b is an inlier if a point of a lies this close after alignment
  double viewpoint_offset_m = 0.05;  ///< b's points as a scan: point i seen from p_i + offset · n_i (orients normals)

  void validate() const {
    ppf.validate();
    match.validate();
    icp.validate();
    detail::require(refined_hypotheses >= 1, "ModelAlignmentSetting::refined_hypotheses must be >= 1, got ",
                    refined_hypotheses);
    detail::require_positive("ModelAlignmentSetting::inlier_radius_m", inlier_radius_m);
    detail::require_positive("ModelAlignmentSetting::viewpoint_offset_m", viewpoint_offset_m);
  }
};

/// The result of align_models.
struct ModelAlignment {
  Pose T_ab = Pose::Identity();  ///< model b's frame → model a's frame
  double score = 0.0;            ///< inliers / points of b at T_ab, in [0, 1]
  double votes = 0.0;            ///< the PPF cluster score of the chosen hypothesis
  std::size_t hypothesis = 0;    ///< its rank among the PPF hypotheses (0: the best voted)
  std::size_t hypotheses = 0;    ///< PPF hypotheses found
  RegistrationResult icp;        ///< the chosen hypothesis's refinement (T_ab = icp.correction · T_PPF if applied)
};

/// The fraction of `points` (moved by T) within r of a point of `tree`.
[[nodiscard]] inline double inlier_fraction(const detail::PointKdTree& tree, const std::vector<Vec3>& points,
                                            const Pose& T, double r) {
  std::size_t in = 0;
  for (const Vec3& p : points) in += tree.any_within(T * p, r) ? 1 : 0;
  return points.empty() ? 0.0 : double(in) / double(points.size());
}

/// T_ab aligning model b onto model a (both oriented points, each in its own session's world frame, metres): the
/// PPF hypotheses T_ba (a → b, best first), each of the best `refined_hypotheses` inverted and refined by Icp (b's
/// points, moved by the hypothesis, registered to a's points; a refused refinement keeps the hypothesis); the one
/// with the highest inlier fraction wins (ties: the better voted). Score 0 and T_ab identity if no pair voted.
/// Deterministic. Throws InvalidArgument for invalid models or setting (PpfModel's limits on model a included).
template <class = void>  // lazy: instantiated where called, not where included (docs/robustness.md)
[[nodiscard]] inline ModelAlignment align_models(const OrientedPoints& a, const OrientedPoints& b,
                                                 const ModelAlignmentSetting& setting = {}) {
  setting.validate();
  a.validate("align_models: model a");
  b.validate("align_models: model b");
  const PpfModel model(a, setting.ppf);
  const std::vector<PoseHypothesis> hyp = match_ppf(model, b, setting.match);
  ModelAlignment best;
  best.hypotheses = hyp.size();
  const detail::PointKdTree tree(a.points);
  const Icp icp(setting.icp);
  for (std::size_t h = 0; h < hyp.size() && h < setting.refined_hypotheses; ++h) {
    const Pose coarse = hyp[h].pose.inverse();  // b → a
    Scan scan;  // b's points in a's frame, point i seen from p_i + offset · n_i
    scan.points.reserve(b.size());
    scan.profile_poses.reserve(b.size());
    for (std::size_t i = 0; i < b.size(); ++i) {
      const Vec3 p = coarse * b.points[i];
      Pose view = Pose::Identity();
      view.translation() = p + setting.viewpoint_offset_m * (coarse.linear() * b.normals[i]);
      scan.profile_poses.push_back(view);
      scan.add_point(p, static_cast<std::uint32_t>(i));
    }
    const RegistrationResult r = icp.register_scan(scan, PlacedOrientedPoints(a, Pose::Identity()));
    const Pose T = r.applied() ? Pose(r.correction * coarse) : coarse;
    const double score = inlier_fraction(tree, b.points, T, setting.inlier_radius_m);
    if (h == 0 || score > best.score) {
      best.T_ab = T;
      best.score = score;
      best.votes = hyp[h].score;
      best.hypothesis = h;
      best.icp = r;
    }
  }
  return best;
}

/// One model of both sessions in a's frame: a's vertices and triangles, then b's moved by T_ab (indices offset by
/// a's vertex count); normals (moved by R_ab) if both have them, else none; vertex colours if both have them, else none. No re-meshing: where both models cover
/// the surface, both layers stay. Throws InvalidArgument if T_ab is not rigid or a model has bad indices/normals.
[[nodiscard]] inline IndexedMesh merge_models(const IndexedMesh& a, const IndexedMesh& b, const Pose& T_ab) {
  validate_pose(T_ab, "merge_models: T_ab");
  for (const IndexedMesh* m : {&a, &b}) {
    detail::require(m->normals.empty() || m->normals.size() == m->vertices.size(), "merge_models: a model has ",
                    m->normals.size(), " normals for ", m->vertices.size(), " vertices");
    detail::require(m->colors.empty() || m->colors.size() == m->vertices.size(), "merge_models: a model has ",
                    m->colors.size(), " colours for ", m->vertices.size(), " vertices");
    for (std::size_t t = 0; t < m->triangles.size(); ++t)
      for (const auto i : m->triangles[t])
        detail::require(i < m->vertices.size(), "merge_models: triangle ", t, " refers to vertex ", i, " of ",
                        m->vertices.size());
  }
  const IndexedMesh moved = transformed_mesh(b, T_ab);
  IndexedMesh out = a;
  const auto base = static_cast<std::uint32_t>(a.vertices.size());
  out.vertices.insert(out.vertices.end(), moved.vertices.begin(), moved.vertices.end());
  for (const auto& t : b.triangles) out.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  if (a.normals.empty() || b.normals.empty()) out.normals.clear();
  else out.normals.insert(out.normals.end(), moved.normals.begin(), moved.normals.end());
  if (a.colors.empty() || b.colors.empty()) out.colors.clear();
  else out.colors.insert(out.colors.end(), b.colors.begin(), b.colors.end());
  return out;
}

}  // namespace nbs
