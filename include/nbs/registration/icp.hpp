// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Local registration of a whole scan to the current model with the thesis's ICP variant (Sec. 3.2.3):
/// correspondences within a radius (3 mm), discarded when their normals differ by more than 60°, point-to-plane
/// error, a small fixed number of iterations (2–3: more iterations contract the model, Fig. 3.6).

#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <vector>

#include "nbs/registration/detail/point_to_plane.hpp"
#include "nbs/registration/registration.hpp"
#include "nbs/registration/scan_normals.hpp"
#include "nbs/sim/detail/point_kd_tree.hpp"

namespace nbs {

/// Settings of Icp. Throws InvalidArgument from validate() naming the bad field.
struct IcpSetting {
  double radius_m = 0.003;            ///< correspondence radius (thesis: 3 mm)
  double max_normal_angle_rad = 60.0 * std::numbers::pi / 180.0;  ///< normal compatibility (thesis: 60°); π = off
  int iterations = 2;                 ///< fixed iteration count (thesis: 2–3); the upper bound with `converge`
  /// Convergence criterion (option): stop early when one iteration's update is below both bounds; then
  /// `iterations` is only the upper bound. Empty: always run `iterations` iterations (the thesis).
  struct Convergence {
    double translation_m = 1e-5;
    double rotation_rad = 1e-5;
    bool operator==(const Convergence&) const = default;
  };
  std::optional<Convergence> converge;
  double normal_radius_m = 0.0;       ///< radius of the scan's normal estimation; 0 = radius_m
  std::size_t min_correspondences = 100;  ///< refuse with fewer scan points with normals or correspondences
  double min_condition = 3e-3;        ///< refuse when λ_min/λ_max of the scaled normal matrix is below
  double max_translation_m = 0.02;    ///< refuse a correction that moves the scan centroid farther
  double max_rotation_rad = 5.0 * std::numbers::pi / 180.0;  ///< refuse a larger correction rotation
  /// Residual trimming (nbs addition): an iteration drops the correspondences whose |point-to-plane residual| exceeds
  /// trim_factor × the median |residual| of that iteration (e.g. scan points beside an edge matched to a vertex whose
  /// normal the mesh blended across the edge). 0 = off (the thesis: every gated correspondence counts).
  double trim_factor = 5.0;

  void validate() const;
  bool operator==(const IcpSetting&) const = default;
};

/// The thesis's ICP (Sec. 3.2.3) as a RegistrationPolicy over any NormalMesh.
///
/// `register_scan(scan, mesh)`:
/// 1. Model: the mesh vertices with a normal inside the scan's bounding box grown by radius_m + max_translation_m +
///    max_rotation_rad·(its diagonal) — every vertex an admissible correction can bring within radius_m; a kd-tree
///    over them (the cost follows the overlap, not the model).
/// 2. Scan normals: estimate_scan_normals with radius normal_radius_m (0: radius_m), oriented to the sensor;
///    points without a normal are not used.
/// 3. Each iteration: every used scan point q = C·p (C the current estimate, identity at first) is matched to the
///    nearest model vertex m within radius_m whose normal n_m satisfies n_m·(C·n_p) ≥ cos(max_normal_angle_rad);
///    with trim_factor > 0, matches with |n_m·(q − m)| above trim_factor × their median are dropped; one linearised
///    point-to-plane step (detail::point_to_plane_step) about the centroid of the matched q; C ← step·C.
///    `iterations` iterations, or fewer when `converge` is set and an update is below both of its bounds.
/// Refusals (correction identity; `reason` names the value and the bound): no model vertex with a normal
/// (refused_empty_model); fewer than min_correspondences scan points with a normal (refused_few_points) or
/// correspondences in an iteration (refused_correspondences); an iteration's condition below min_condition
/// (refused_degenerate: a plane, a sphere, a sphere beside one plane do not fix all six DoF); the estimate moves the
/// centroid of the used scan points farther than max_translation_m or rotates more than max_rotation_rad
/// (refused_large_correction).
/// Throws InvalidArgument for an invalid setting, or an invalid scan (Scan::validate; not checked again by the
/// prevalidated_scan form, which NbsPlanner::integrate calls after its own check). Cost O(n + k log k + i·n log k)
/// for n scan points, k cropped model vertices and i iterations; serial and deterministic (bit-identical results for
/// the same input). Const: concurrent calls on one Icp are safe.
class Icp {
public:
  IcpSetting setting{};

  Icp() { setting.validate(); }
  explicit Icp(const IcpSetting& s) : setting(s) { setting.validate(); }

  /// Validates `scan` (Scan::validate: InvalidArgument, nothing computed), then registers it.
  template <NormalMesh Mesh>
  [[nodiscard]] RegistrationResult register_scan(const Scan& scan, const Mesh& mesh) const {
    const auto t0 = std::chrono::steady_clock::now();
    scan.validate();
    return run(scan, mesh, t0);
  }
  /// The same for a scan the caller has validated already (NbsPlanner::integrate): no second O(n) check.
  template <NormalMesh Mesh>
  [[nodiscard]] RegistrationResult register_scan(const Scan& scan, const Mesh& mesh, PrevalidatedScan) const {
    return run(scan, mesh, std::chrono::steady_clock::now());
  }

private:
  template <NormalMesh Mesh>
  [[nodiscard]] RegistrationResult run(const Scan& scan, const Mesh& mesh,
                                       std::chrono::steady_clock::time_point t0) const;
};

inline void IcpSetting::validate() const {
  detail::require_positive("IcpSetting::radius_m", radius_m);
  detail::require(std::isfinite(max_normal_angle_rad) && max_normal_angle_rad > 0.0 &&
                      max_normal_angle_rad <= std::numbers::pi,
                  "IcpSetting::max_normal_angle_rad must be in (0, pi], got ", max_normal_angle_rad);
  detail::require(iterations >= 1 && iterations <= 100, "IcpSetting::iterations must be in [1, 100], got ",
                  iterations);
  if (converge) {
    detail::require_positive("IcpSetting::converge.translation_m", converge->translation_m);
    detail::require_positive("IcpSetting::converge.rotation_rad", converge->rotation_rad);
  }
  detail::require_non_negative("IcpSetting::normal_radius_m", normal_radius_m);
  detail::require(min_correspondences >= 6, "IcpSetting::min_correspondences must be >= 6, got ",
                  min_correspondences);
  detail::require(std::isfinite(min_condition) && min_condition > 0.0 && min_condition < 1.0,
                  "IcpSetting::min_condition must be in (0, 1), got ", min_condition);
  detail::require_positive("IcpSetting::max_translation_m", max_translation_m);
  detail::require(std::isfinite(trim_factor) && (trim_factor == 0.0 || trim_factor >= 1.0),
                  "IcpSetting::trim_factor must be 0 (off) or >= 1, got ", trim_factor);
  detail::require(std::isfinite(max_rotation_rad) && max_rotation_rad > 0.0 && max_rotation_rad <= std::numbers::pi,
                  "IcpSetting::max_rotation_rad must be in (0, pi], got ", max_rotation_rad);
}

template <NormalMesh Mesh>
RegistrationResult Icp::run(const Scan& scan, const Mesh& mesh, std::chrono::steady_clock::time_point t0) const {
  setting.validate();
  const IcpSetting& s = setting;
  RegistrationResult r;
  auto finish = [&](RegistrationStatus status, std::string reason = {}) {
    r.status = status;
    r.reason = std::move(reason);
    if (status != RegistrationStatus::applied) r.correction = Pose::Identity();
    r.t_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
  };

  // Model: vertices with a normal that an admissible correction can bring within radius_m of the scan.
  Aabb box;
  for (const Vec3& p : scan.points) box.extend(p);
  const double grow = box.empty() ? 0.0
                                  : s.radius_m + s.max_translation_m +
                                        s.max_rotation_rad * (box.max - box.min).norm();
  const Vec3 lo = box.min - Vec3::Constant(grow), hi = box.max + Vec3::Constant(grow);
  std::vector<Vec3> model_points, model_normals;
  std::size_t with_normal = 0;
  const std::size_t vertices = mesh.vertex_count();
  for (std::size_t v = 0; v < vertices; ++v) {
    const auto id = static_cast<VertexId>(v);
    if (!mesh.has_normal(id)) continue;
    ++with_normal;
    const Vec3 p = mesh.position(id);
    if ((p.array() < lo.array()).any() || (p.array() > hi.array()).any()) continue;
    model_points.push_back(p);
    model_normals.push_back(Vec3(mesh.normal(id)).normalized());
  }
  if (with_normal == 0)
    return finish(RegistrationStatus::refused_empty_model,
                  detail::concat("the model has no vertex with a normal (", vertices, " vertices)"));

  // Scan normals.
  const std::vector<Vec3> normals =
      estimate_scan_normals(scan, {.radius_m = s.normal_radius_m > 0.0 ? s.normal_radius_m : s.radius_m});
  std::vector<std::uint32_t> used;
  used.reserve(scan.size());
  Vec3 centroid = Vec3::Zero();
  for (std::size_t i = 0; i < scan.size(); ++i)
    if (normals[i].squaredNorm() > 0.0) used.push_back(static_cast<std::uint32_t>(i)), centroid += scan.points[i];
  r.scan_points = used.size();
  if (used.size() < s.min_correspondences)
    return finish(RegistrationStatus::refused_few_points,
                  detail::concat(used.size(), " of ", scan.size(), " scan points have a normal (radius ",
                                 s.normal_radius_m > 0.0 ? s.normal_radius_m : s.radius_m, " m), fewer than ",
                                 "min_correspondences = ", s.min_correspondences));
  centroid /= static_cast<double>(used.size());
  if (model_points.size() < s.min_correspondences)
    return finish(RegistrationStatus::refused_correspondences,
                  detail::concat(model_points.size(), " model vertices with a normal near the scan (of ", with_normal,
                                 "), fewer than min_correspondences = ", s.min_correspondences));

  const detail::PointKdTree model(std::move(model_points));
  const std::vector<Vec3>& mp = model.points();
  const double cos_gate = std::cos(s.max_normal_angle_rad);
  std::vector<detail::PlaneCorrespondence> corr;
  std::vector<double> abs_residuals;
  corr.reserve(used.size());
  Pose estimate = Pose::Identity();
  Pose last_update = Pose::Identity();
  double min_condition = std::numeric_limits<double>::infinity();
  for (int it = 0; it < s.iterations; ++it) {
    corr.clear();
    const Mat3 rot = estimate.linear();
    for (const std::uint32_t i : used) {
      const Vec3 q = estimate * scan.points[i];
      const Vec3 n = rot * normals[i];
      const std::size_t best =
          model.nearest_within(q, s.radius_m, [&](std::size_t j) { return model_normals[j].dot(n) >= cos_gate; })
              .first;
      if (best == mp.size()) continue;
      corr.push_back({q, model_normals[best], model_normals[best].dot(q - mp[best])});
    }
    if (s.trim_factor > 0.0 && !corr.empty()) {
      abs_residuals.resize(corr.size());
      for (std::size_t k = 0; k < corr.size(); ++k) abs_residuals[k] = std::abs(corr[k].r);
      const auto mid = abs_residuals.begin() + static_cast<std::ptrdiff_t>(abs_residuals.size() / 2);
      std::nth_element(abs_residuals.begin(), mid, abs_residuals.end());
      const double bound = s.trim_factor * *mid;
      std::erase_if(corr, [bound](const detail::PlaneCorrespondence& k) { return std::abs(k.r) > bound; });
    }
    r.correspondences = corr.size();
    r.iterations = it + 1;
    if (corr.size() < s.min_correspondences)
      return finish(RegistrationStatus::refused_correspondences,
                    detail::concat(corr.size(), " correspondences in iteration ", it + 1, " (radius ", s.radius_m,
                                   " m, normal gate ", s.max_normal_angle_rad, " rad), fewer than ",
                                   "min_correspondences = ", s.min_correspondences));
    const detail::PointToPlaneStep step = detail::point_to_plane_step(corr);
    if (it == 0) r.rms_before_m = step.rms_m;
    min_condition = std::min(min_condition, step.condition);
    r.condition = min_condition;
    if (!(step.condition >= s.min_condition))
      return finish(RegistrationStatus::refused_degenerate,
                    detail::concat("condition lambda_min/lambda_max = ", step.condition, " in iteration ", it + 1,
                                   " below min_condition = ", s.min_condition, " (", corr.size(),
                                   " correspondences do not fix all six degrees of freedom)"));
    estimate = step.update * estimate;
    last_update = step.update;
    const double moved = (estimate * centroid - centroid).norm();
    const double angle = Eigen::AngleAxisd(estimate.linear()).angle();
    if (moved > s.max_translation_m)
      return finish(RegistrationStatus::refused_large_correction,
                    detail::concat("the correction moves the scan centroid by ", moved, " m in iteration ", it + 1,
                                   ", more than max_translation_m = ", s.max_translation_m));
    if (angle > s.max_rotation_rad)
      return finish(RegistrationStatus::refused_large_correction,
                    detail::concat("the correction rotates by ", angle, " rad in iteration ", it + 1,
                                   ", more than max_rotation_rad = ", s.max_rotation_rad));
    if (s.converge) {
      const double dt = (step.update * centroid - centroid).norm();
      const double da = Eigen::AngleAxisd(step.update.linear()).angle();
      if (dt < s.converge->translation_m && da < s.converge->rotation_rad) break;
    }
  }
  // Residuals of the last correspondences after the last update: r' = r + n·(U·q − q).
  double r2 = 0.0;
  for (const detail::PlaneCorrespondence& k : corr) {
    const double e = k.r + k.n.dot(last_update * k.q - k.q);
    r2 += e * e;
  }
  r.rms_after_m = std::sqrt(r2 / static_cast<double>(corr.size()));
  r.correction = estimate;
  return finish(RegistrationStatus::applied);
}

}  // namespace nbs
