// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// ICP refinement of a verified pose hypothesis (thesis Sec. 3.4: "for fine alignment of the models, the ICP
/// algorithm (see Section 3.2.3) is run"), with the registration module's Icp: the cluster is the scan, the model's
/// oriented points at the hypothesis pose are the surface it is registered to (point-to-plane on the model normals).

#include <cmath>
#include <numbers>
#include <span>

#include "nbs/core/error.hpp"
#include "nbs/core/scan.hpp"
#include "nbs/recognition/oriented_points.hpp"
#include "nbs/registration/icp.hpp"

namespace nbs {

/// OrientedPoints (model frame) placed at T_WM, borrowed, as a NormalMesh (registration.hpp): vertex v is
/// T_WM · points[v] with normal R_WM · normals[v]. The points must outlive the view.
class PlacedOrientedPoints {
public:
  PlacedOrientedPoints(const OrientedPoints& points, const Pose& model_pose) : p_(&points), pose_(model_pose) {}
  [[nodiscard]] std::size_t vertex_count() const { return p_->size(); }
  [[nodiscard]] Vec3 position(VertexId v) const { return pose_ * p_->points[v]; }
  [[nodiscard]] Vec3 normal(VertexId v) const { return pose_.linear() * p_->normals[v]; }
  [[nodiscard]] bool has_normal(VertexId) const { return true; }

private:
  const OrientedPoints* p_;
  Pose pose_;
};
static_assert(NormalMesh<PlacedOrientedPoints>);

/// Icp settings for refining a PPF hypothesis (a few mm and degrees off, Sec. 3.4) rather than a robot's pose
/// error: 10 mm correspondence radius, 6 mm normal radius, up to 30 iterations until an update is below 10 µm and
/// 10 µrad, corrections up to 30 mm and 15°, at least 30 correspondences.
[[nodiscard]] inline IcpSetting recognition_icp_setting() {
  IcpSetting s;
  s.radius_m = 0.01;
  s.normal_radius_m = 0.006;
  s.iterations = 30;
  s.converge = IcpSetting::Convergence{1e-5, 1e-5};
  s.max_translation_m = 0.03;
  s.max_rotation_rad = 15.0 * std::numbers::pi / 180.0;
  s.min_correspondences = 30;
  return s;
}

/// A refined hypothesis: the pose and the Icp's result (its correction C moved the cluster onto the model).
struct RefinedPose {
  Pose pose = Pose::Identity();  ///< T_WM after refinement; the input pose if the Icp refused
  RegistrationResult icp;
};

/// Refines T_WM = `model_pose` of `model` (oriented points, model frame, e.g. dense surface samples of the
/// database mesh) against `cluster` (an area-sensor Scan holding only the cluster's points, world frame; its profile
/// pose orients the estimated normals): Icp registers the cluster to the placed model, C · cluster ≈ T_WM · model,
/// so the refined pose is C⁻¹ · T_WM. Throws InvalidArgument for an invalid model, pose, scan or setting.
template <class = void>  // lazy: instantiated where called, not where included (docs/robustness.md)
[[nodiscard]] inline RefinedPose refine_pose(const OrientedPoints& model, const Pose& model_pose, const Scan& cluster,
                                             const IcpSetting& setting = recognition_icp_setting()) {
  model.validate("refine_pose: model");
  validate_pose(model_pose, "refine_pose: model_pose");
  const Icp icp(setting);
  RefinedPose out;
  out.icp = icp.register_scan(cluster, PlacedOrientedPoints(model, model_pose));
  out.pose = out.icp.applied() ? Pose(out.icp.correction.inverse() * model_pose) : model_pose;
  return out;
}

}  // namespace nbs
