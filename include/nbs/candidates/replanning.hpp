// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Replanning for occlusions and collisions (Sec. 4.5.2, Alg. 3, Eq. 4.29): a scan path candidate is rotated about
/// its target surface point, about the sensor x and y axes by 0, ±10°, …, ±40°, until ≥ 50 % of its target points
/// are visible (ray casts in the voxel space) and ≥ 50 % of the path is collision-free; otherwise it is dropped.
///
/// Our reading of Alg. 3 (frames: world W and sensor S of types.hpp, metres, radians):
/// - s'_z = R(s_y, β_y) · R(s_x, β_x) · s_z with the original axes (Eq. 4.29);
/// - d_b := s_y (generators make s_y the boundary direction made orthogonal to s_z); s'_y = d_b made orthogonal
///   to s'_z, s'_x = s'_y × s'_z (Eqs. 4.16–4.17 in a right-handed frame, as in Boundary Search). For the angles
///   of Alg. 3 this equals the rigid rotation R(s_y, β_y)·R(s_x, β_x) of (s_x, s_y, s_z);
/// - the surface points at the path ends, p_i = s_p^i + d_s·s_z with d_s = (aim − s_p¹)·s_z, stay; the new ends are
///   s'_p^i = p_i − d_s·s'_z (Eq. 4.18). So the aim point and every point of the segment p_1 p_2 stay at distance
///   d_s along s'_z from the corresponding path position; the path keeps its direction (∥ d_b).
/// - Occlusion: the sensor is sampled along the path in portions of 10 mm; a target counts as visible if from some
///   sample it is in view (detail::in_view: FOV, working range, incidence) and the ray from the sample to the
///   target, shortened by `target_clearance_voxels`·l_v, meets no occupied voxel.
/// - Collision: collision_free_fraction (collision.hpp), checked only when the occlusion test passed (Sec. 4.5.2).
/// - Robot (issue 19): an optional `PathAcceptor` runs last on a rotation that passed both tests (e.g. "can the arm
///   fly this path", NbsPlanner's RobotReach); a refused rotation is skipped like a colliding one. Default: accept.

#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <span>
#include <string_view>
#include <vector>

#include "nbs/candidates/collision.hpp"
#include "nbs/candidates/detail/replanning_visibility.hpp"
#include "nbs/candidates/planning_context.hpp"
#include "nbs/candidates/scan_candidate.hpp"

namespace nbs {

/// Parameters of Alg. 3. Defaults: the thesis (10° steps up to 40°, 50 % / 50 %, 10 mm portions, 70° incidence).
struct ReplanSetting {
  double angle_step_rad = 10.0 * std::numbers::pi / 180.0;  ///< step of β_x and β_y
  int angle_steps = 4;                                       ///< largest |β| = angle_steps · angle_step_rad
  double min_visible_fraction = 0.5;         ///< accept when at least this part of the targets is visible
  double min_collision_free_fraction = 0.5;  ///< ... and at least this part of the path portions is free
  double portion_m = 0.01;                   ///< path portion for sampling (Sec. 3.2.2)
  double incidence_cutoff_rad = 70.0 * std::numbers::pi / 180.0;  ///< Tab. 4.3
  double target_clearance_voxels = 2.0;  ///< rays stop this many voxel edges before the target (its own surface
                                         ///< voxels are not occluders). Our choice.
  /// z (world, metres) of the support plane the object stands on (pedestal or table top, Sec. 4.1); the half-space
  /// below it is solid, so a rotation whose start or end position lies below it is rejected outright (no 50 % rule:
  /// a sensor inside the table sees nothing). −∞ (default): no support plane. NbsPlanner sets the bottom of the
  /// bounding box of the unknown area.
  double support_plane_z_m = -std::numeric_limits<double>::infinity();

  /// Throws InvalidArgument naming the first bad field (the largest angle must be < 90°).
  void validate() const {
    detail::require_positive("angle_step_rad", angle_step_rad);
    detail::require(angle_steps >= 0 && angle_steps <= 1000, "angle_steps must be in [0, 1000], got ", angle_steps);
    detail::require(angle_steps * angle_step_rad < 0.5 * std::numbers::pi, "angle_steps * angle_step_rad must be < ",
                    "pi/2, got ", angle_steps * angle_step_rad);
    detail::require_in_range("min_visible_fraction", min_visible_fraction, 0.0, 1.0);
    detail::require_in_range("min_collision_free_fraction", min_collision_free_fraction, 0.0, 1.0);
    detail::require_positive("portion_m", portion_m);
    detail::require_in_range("incidence_cutoff_rad", incidence_cutoff_rad, 0.0, std::numbers::pi / 2.0);
    detail::require_non_negative("target_clearance_voxels", target_clearance_voxels);
    detail::require(!std::isnan(support_plane_z_m) && support_plane_z_m < std::numeric_limits<double>::infinity(),
                    "support_plane_z_m must be finite or -inf, got ", support_plane_z_m);
  }
  /// True if both ends of `path` (hence all of it) lie on or above the support plane.
  [[nodiscard]] bool above_support(const LinearScanPath& path) const {
    return path.start().position().z() >= support_plane_z_m && path.end_position().z() >= support_plane_z_m;
  }
};

/// What Alg. 3 did with one candidate.
enum class ReplanOutcome : std::uint8_t {
  unchanged,             ///< the unrotated path passed
  rotated,               ///< a rotation (β_x, β_y) ≠ (0, 0) passed; the path was replaced
  dropped_occluded,      ///< no rotation saw enough targets
  dropped_in_collision,  ///< some rotations saw enough targets, but each of them collided too much
  dropped_unreachable,   ///< some rotations passed occlusion and collision, but the PathAcceptor refused each
};

[[nodiscard]] constexpr std::string_view to_string(ReplanOutcome o) {
  switch (o) {
    case ReplanOutcome::unchanged: return "unchanged";
    case ReplanOutcome::rotated: return "rotated";
    case ReplanOutcome::dropped_occluded: return "dropped: occluded for every rotation";
    case ReplanOutcome::dropped_in_collision: return "dropped: in collision for every unoccluded rotation";
    case ReplanOutcome::dropped_unreachable: return "dropped: the robot cannot execute any free unoccluded rotation";
  }
  return "unknown outcome";
}

/// Report of replan(). Fractions are those of the accepted rotation; for a dropped candidate the best values
/// seen (collision_free_fraction over the rotations that passed the occlusion test, 0 if none did).
struct ReplanReport {
  ReplanOutcome outcome = ReplanOutcome::unchanged;
  double beta_x_rad = 0.0;  ///< accepted rotation about s_x (0 unless rotated)
  double beta_y_rad = 0.0;  ///< accepted rotation about s_y (0 unless rotated)
  double visible_fraction = 0.0;
  double collision_free_fraction = 0.0;
  int rotations_tried = 0;    ///< 1 … (2·angle_steps + 1)²
  int collision_checks = 0;   ///< rotations whose collision test ran
  int acceptor_checks = 0;    ///< rotations the PathAcceptor was asked about (passed occlusion and collision)
  int acceptor_refusals = 0;  ///< of them refused
  [[nodiscard]] bool accepted() const {
    return outcome == ReplanOutcome::unchanged || outcome == ReplanOutcome::rotated;
  }
};

/// A final test of a replanned path: `a(path)` is true if the path may be kept (e.g. the robot can fly it).
template <class A>
concept PathAcceptor = requires(const A& a, const LinearScanPath& path) {
  { a(path) } -> std::convertible_to<bool>;
};

/// Accepts every path (Alg. 3 as written).
struct AcceptAnyPath {
  [[nodiscard]] bool operator()(const LinearScanPath&) const { return true; }
};

/// R(a, β) of Eq. 4.29 (its 3 × 3 part): a aᵀ + cos β (I − a aᵀ) + sin β [a]×, the right-handed rotation by β about
/// the unit axis a. Throws InvalidArgument unless a is finite with |a| = 1 ± 1e-9 and β is finite.
[[nodiscard]] inline Mat3 axis_rotation(const Vec3& a, double beta) {
  detail::require(a.allFinite() && std::abs(a.norm() - 1.0) <= 1e-9, "axis_rotation: axis must be unit, got (",
                  a.transpose(), ")");
  detail::require(std::isfinite(beta), "axis_rotation: angle must be finite, got ", beta);
  Mat3 skew;
  skew << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  const Mat3 aat = a * a.transpose();
  return aat + std::cos(beta) * (Mat3::Identity() - aat) + std::sin(beta) * skew;
}

/// The angles of Alg. 3 in the thesis order: 0, +step, −step, +2·step, −2·step, …, ±steps·step (radians).
[[nodiscard]] inline std::vector<double> alg3_angles(double step_rad, int steps) {
  std::vector<double> out{0.0};
  for (int k = 1; k <= steps; ++k) {
    out.push_back(k * step_rad);
    out.push_back(-k * step_rad);
  }
  return out;
}

/// The path of Alg. 3 for rotation (β_x, β_y) about `aim` (see the file comment). Throws InvalidArgument if aim
/// is not finite or does not lie in front of the start pose ((aim − s_p¹)·s_z ≤ 0), or |β| ≥ 90°.
[[nodiscard]] inline LinearScanPath rotate_scan_path(const LinearScanPath& path, const Vec3& aim, double beta_x_rad,
                                                     double beta_y_rad) {
  validate_finite(aim, "replanning aim");
  detail::require(std::abs(beta_x_rad) < 0.5 * std::numbers::pi && std::abs(beta_y_rad) < 0.5 * std::numbers::pi,
                  "rotate_scan_path: |beta| must be < pi/2, got ", beta_x_rad, ", ", beta_y_rad);
  const Viewpoint& s = path.start();
  const Vec3 s_x = s.x_axis(), s_y = s.y_axis(), s_z = s.view_direction();
  const double d_s = (aim - s.position()).dot(s_z);
  detail::require(d_s > 0.0, "replanning aim lies behind the sensor (distance along s_z ", d_s, " m)");
  const Vec3 z = axis_rotation(s_y, beta_y_rad) * (axis_rotation(s_x, beta_x_rad) * s_z);  // Alg. 3, Eq. 4.29
  const Vec3 y = (s_y - s_y.dot(z) * z).normalized();                                         // Eqs. 4.16–4.17
  const Vec3 x = y.cross(z);
  const Vec3 p1 = s.position() + d_s * s_z, p2 = path.end_position() + d_s * s_z;
  const Viewpoint start = Viewpoint::from_axes(x, y, z, p1 - d_s * z);  // Eq. 4.18
  return LinearScanPath(start, p2 - d_s * z);
}

/// Fraction of `targets` visible from the path (see the file comment); 0 for no targets. Throws InvalidArgument
/// if the sensor or setting is invalid or a target is not finite.
template <VoxelSpace Space>
[[nodiscard]] double visible_fraction(const Space& space, const LinearScanPath& path,
                                      std::span<const SurfaceTarget> targets, const SensorGeometry& sensor,
                                      const ReplanSetting& setting = {}) {
  sensor.validate();
  setting.validate();
  for (const SurfaceTarget& t : targets) {
    validate_finite(t.point, "replanning target point");
    validate_finite(t.normal, "replanning target normal");
  }
  if (targets.empty()) return 0.0;
  const std::size_t n = path.length() > 0.0 ? path_portions(path.length(), setting.portion_m) : 0;
  const double fan_tolerance = 0.5 * (n > 0 ? path.length() / static_cast<double>(n) : setting.portion_m);
  const double clearance = setting.target_clearance_voxels * space.resolution_m();
  std::size_t visible = 0;
  for (const SurfaceTarget& t : targets) {
    for (std::size_t k = 0; k <= n; ++k) {
      const Pose pose = path.pose_at(n > 0 ? static_cast<double>(k) / static_cast<double>(n) : 0.0);
      if (!detail::in_view(pose, t, sensor, fan_tolerance, setting.incidence_cutoff_rad)) continue;
      const Vec3 o = pose.translation();
      const double d = (t.point - o).norm();
      const Vec3 end = o + std::max(0.0, d - clearance) / d * (t.point - o);
      if (!space.cast_ray(Ray{o, end}, detail::ContinueVisit{}).hit) {
        ++visible;
        break;
      }
    }
  }
  return static_cast<double>(visible) / static_cast<double>(targets.size());
}

/// Alg. 3 on one scan path. On acceptance `path` is replaced by the accepted rotation (unchanged for (0, 0));
/// when dropped it is left as it was. `targets` must not be empty. Throws InvalidArgument (path unchanged) on an
/// invalid setting or sensor, empty or non-finite targets, or an aim behind the sensor. `accept` runs last on a
/// rotation that passed occlusion and collision (see the file comment).
/// Deterministic; thread-safe if the space and the checker are only read.
template <VoxelSpace Space, CollisionChecker Checker, PathAcceptor Accept = AcceptAnyPath>
[[nodiscard]] ReplanReport replan(LinearScanPath& path, const Vec3& aim, std::span<const SurfaceTarget> targets,
                                  const Space& space, const Checker& checker, const SensorGeometry& sensor,
                                  const ReplanSetting& setting = {}, const Accept& accept = {}) {
  setting.validate();
  sensor.validate();
  detail::require(!targets.empty(), "replan: the candidate has no target surface point");
  ReplanReport report;
  report.outcome = ReplanOutcome::dropped_occluded;
  const std::vector<double> angles = alg3_angles(setting.angle_step_rad, setting.angle_steps);
  bool any_above_support = false;
  for (const double bx : angles)
    for (const double by : angles) {
      const LinearScanPath candidate = rotate_scan_path(path, aim, bx, by);
      ++report.rotations_tried;
      if (!setting.above_support(candidate)) continue;
      any_above_support = true;
      const double vis = visible_fraction(space, candidate, targets, sensor, setting);
      report.visible_fraction = std::max(report.visible_fraction, vis);
      if (vis < setting.min_visible_fraction) continue;
      ++report.collision_checks;
      report.outcome = ReplanOutcome::dropped_in_collision;
      const double free = collision_free_fraction(checker, candidate, setting.portion_m);
      report.collision_free_fraction = std::max(report.collision_free_fraction, free);
      if (free < setting.min_collision_free_fraction) continue;
      ++report.acceptor_checks;
      if (!static_cast<bool>(accept(candidate))) {
        ++report.acceptor_refusals;
        report.outcome = ReplanOutcome::dropped_unreachable;
        continue;
      }
      report.outcome = (bx == 0.0 && by == 0.0) ? ReplanOutcome::unchanged : ReplanOutcome::rotated;
      report.beta_x_rad = bx;
      report.beta_y_rad = by;
      report.visible_fraction = vis;
      report.collision_free_fraction = free;
      path = candidate;
      return report;
    }
  if (report.acceptor_refusals > 0) report.outcome = ReplanOutcome::dropped_unreachable;
  if (!any_above_support) report.outcome = ReplanOutcome::dropped_in_collision;  // inside the support everywhere
  return report;
}

/// Alg. 3 on a ScanCandidate: pivot `aim.point`, targets `targets` (or `{aim}` if empty). After a rotation with
/// β_x ≠ 0 the path still runs along the old s_y (in the s'_y–s'_z plane): the aim is at d_s along s'_z from the
/// path point of its own parameter, but ScanCandidate's invariant (offset from s'_p¹ ∥ s'_y) holds only for β_x = 0.
template <VoxelSpace Space, CollisionChecker Checker, PathAcceptor Accept = AcceptAnyPath>
[[nodiscard]] ReplanReport replan(ScanCandidate& candidate, const Space& space, const Checker& checker,
                                  const SensorGeometry& sensor, const ReplanSetting& setting = {},
                                  const Accept& accept = {}) {
  const std::span<const SurfaceTarget> targets =
      candidate.targets.empty() ? std::span<const SurfaceTarget>(&candidate.aim, 1)
                                : std::span<const SurfaceTarget>(candidate.targets);
  return replan(candidate.path, candidate.aim.point, targets, space, checker, sensor, setting, accept);
}

/// Alg. 3 on every candidate (Sec. 4.5.2: before the NBS is selected): replans the accepted ones in place, erases
/// the dropped ones (order of the rest kept) and returns one report per input candidate, in input order.
template <VoxelSpace Space, CollisionChecker Checker>
[[nodiscard]] std::vector<ReplanReport> replan_candidates(std::vector<ScanCandidate>& candidates, const Space& space,
                                                          const Checker& checker, const SensorGeometry& sensor,
                                                          const ReplanSetting& setting = {}) {
  std::vector<ReplanReport> reports;
  reports.reserve(candidates.size());
  std::vector<ScanCandidate> kept;
  for (ScanCandidate& c : candidates) {
    ScanCandidate copy = c;
    reports.push_back(replan(copy, space, checker, sensor, setting));
    if (reports.back().accepted()) kept.push_back(std::move(copy));
  }
  candidates = std::move(kept);
  return reports;
}

}  // namespace nbs
