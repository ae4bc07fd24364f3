// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The registration step of the planner (Sec. 3.2.3): before a scan is integrated, a `RegistrationPolicy` may
/// correct its pose against the current model. The result is a rigid correction C (world → world) that the planner
/// applies to the whole scan (profile poses C·T_WS, points C·p), or a refusal that leaves the scan as measured.
/// `NoRegistration` (the default, for exact poses) never changes a scan.

#include <chrono>
#include <concepts>
#include <cstdint>
#include <string>
#include <string_view>

#include "nbs/core/error.hpp"
#include "nbs/core/scan.hpp"
#include "nbs/core/types.hpp"
#include "nbs/mesh/mesh_concept.hpp"

namespace nbs {

/// What a registration step did with a scan.
enum class RegistrationStatus : std::uint8_t {
  not_run,                 ///< no registration configured (NoRegistration)
  applied,                 ///< the correction was applied to the scan
  refused_empty_model,     ///< the model has no vertex with a normal yet (first scan)
  refused_few_points,      ///< the scan has too few points with an estimable normal
  refused_correspondences, ///< too few correspondences (too little overlap)
  refused_degenerate,      ///< the point-to-plane system does not constrain all six degrees of freedom
  refused_large_correction ///< the correction exceeds the setting's bound (a pose error that large is not trusted)
};

[[nodiscard]] constexpr std::string_view to_string(RegistrationStatus s) {
  switch (s) {
    case RegistrationStatus::not_run: return "not_run";
    case RegistrationStatus::applied: return "applied";
    case RegistrationStatus::refused_empty_model: return "refused_empty_model";
    case RegistrationStatus::refused_few_points: return "refused_few_points";
    case RegistrationStatus::refused_correspondences: return "refused_correspondences";
    case RegistrationStatus::refused_degenerate: return "refused_degenerate";
    case RegistrationStatus::refused_large_correction: return "refused_large_correction";
  }
  return "?";
}

/// Outcome of one registration step, reported in IntegrationReport::registration.
struct RegistrationResult {
  RegistrationStatus status = RegistrationStatus::not_run;
  /// Rigid correction C (world → world): the registered scan is C·scan. Identity unless status == applied.
  Pose correction = Pose::Identity();
  std::size_t scan_points = 0;        ///< scan points used (with an estimable normal)
  std::size_t correspondences = 0;    ///< correspondences in the last iteration
  int iterations = 0;                 ///< iterations run
  double rms_before_m = 0.0;          ///< point-to-plane RMS of the first iteration's correspondences, metres
  double rms_after_m = 0.0;           ///< same after the correction (last iteration's correspondences), metres
  double condition = 0.0;             ///< smallest λ_min / λ_max of the scaled 6×6 normal matrix over the iterations run
  double t_s = 0.0;                   ///< wall-clock time of the step, seconds
  std::string reason;                 ///< for a refusal: what was measured against which bound

  [[nodiscard]] bool applied() const { return status == RegistrationStatus::applied; }
};

/// A copy of `scan` moved rigidly by `correction` (world → world): profile poses C·T_WS, points C·p (colours kept).
/// Throws InvalidArgument if `correction` is not finite and rigid.
[[nodiscard]] inline Scan transformed(const Scan& scan, const Pose& correction) {
  validate_pose(correction, "registration correction");
  Scan out = scan;
  for (Pose& p : out.profile_poses) p = correction * p;
  for (Vec3& x : out.points) x = correction * x;
  return out;
}

/// Tag of the three-argument `register_scan(scan, mesh, prevalidated_scan)`: the caller has already checked `scan`
/// with Scan::validate (NbsPlanner::integrate does, before anything changes), so the policy skips its own O(n)
/// check. The two-argument form, the one for user input, always validates.
struct PrevalidatedScan {
  explicit PrevalidatedScan() = default;
};
inline constexpr PrevalidatedScan prevalidated_scan{};

/// True if policy R offers the prevalidated form (NbsPlanner then calls it after its own Scan::validate).
template <class R, class Mesh>
concept TakesPrevalidatedScan = requires(R& r, const Scan& scan, const Mesh& mesh) {
  { r.register_scan(scan, mesh, prevalidated_scan) } -> std::same_as<RegistrationResult>;
};

/// A model with per-vertex normals that a scan can be registered to (StreamingMesh, NoiseRobustStreamingMesh).
template <class M>
concept NormalMesh = requires(const M& m, VertexId v) {
  { m.vertex_count() } -> std::convertible_to<std::size_t>;
  { m.position(v) } -> std::convertible_to<Vec3>;
  { m.normal(v) } -> std::convertible_to<Vec3>;
  { m.has_normal(v) } -> std::convertible_to<bool>;
};

/// The planner's registration policy: `r.register_scan(scan, mesh)` returns the correction of a valid `scan`
/// against the current model `mesh` (world frame) or a refusal; it must not change the mesh. Called by
/// NbsPlanner::integrate after Scan::validate and before anything changes.
template <class R, class Mesh>
concept RegistrationPolicy = requires(R& r, const Scan& scan, const Mesh& mesh) {
  { r.register_scan(scan, mesh) } -> std::same_as<RegistrationResult>;
};

/// Exact poses (simulation, or a robot whose error is negligible): never changes a scan (status not_run).
struct NoRegistration {
  template <class Mesh>
  [[nodiscard]] RegistrationResult register_scan(const Scan&, const Mesh&) const {
    return {};
  }
};

}  // namespace nbs
