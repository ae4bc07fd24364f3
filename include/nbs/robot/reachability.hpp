// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Can the robot fly a linear scan path (Sec. 4.3.2) with the sensor? `check_scan_path` samples T_WS along the path,
/// solves IK at each sample from the previous sample's solution and rejects a step whose joints jump or leave their
/// limits. Collisions are not checked here: a `ConfigurationCheck` is the extension point and runs on every sampled
/// configuration; `RobotPathChecker` (robot/link_collision.hpp) plugs in the links against the voxel space.

#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "nbs/core/scan_path.hpp"
#include "nbs/core/viewpoint.hpp"
#include "nbs/robot/robot.hpp"

namespace nbs {

/// Sampling and jump bound of `check_scan_path`.
struct ScanPathReachSetting {
  /// Largest distance between two sampled sensor positions, metres (> 0).
  double max_sample_step_m = 0.01;
  /// Largest change of any joint between two consecutive samples, in the joint's unit (radians for revolute joints,
  /// metres for prismatic ones; > 0). A larger change is a jump (an IK branch switch, a singularity), rejected.
  double max_joint_step = 0.2;

  void validate() const {
    detail::require_positive("ScanPathReachSetting::max_sample_step_m", max_sample_step_m);
    detail::require_positive("ScanPathReachSetting::max_joint_step", max_joint_step);
  }
};

/// Why a path is not flown.
enum class PathFailure {
  none,                   ///< reachable
  unreachable,            ///< IK found no solution at the step (value: the step's arc-length fraction t ∈ [0, 1])
  joint_jump,             ///< value: the largest joint change to the previous step
  joint_limit,            ///< value: the joint's value outside its limits
  configuration_rejected,  ///< the ConfigurationCheck refused the step (value: t ∈ [0, 1])
  collision                ///< a link collides at the step (RobotPathChecker; `link` names it; value: t ∈ [0, 1])
};

[[nodiscard]] inline std::string_view to_string(PathFailure f) {
  switch (f) {
    case PathFailure::none: return "none";
    case PathFailure::unreachable: return "unreachable";
    case PathFailure::joint_jump: return "joint_jump";
    case PathFailure::joint_limit: return "joint_limit";
    case PathFailure::configuration_rejected: return "configuration_rejected";
    case PathFailure::collision: return "collision";
  }
  return "?";
}

/// The outcome of `check_scan_path`: the joint trajectory (one q per sample, sample i at t = i / (samples − 1)), or
/// the failure with the failing sample index, the joint concerned (−1 if none) and the value described at
/// `PathFailure`. On a failure `joints` holds the samples before the failing one.
struct ScanPathReach {
  std::vector<JointVector> joints;
  PathFailure failure = PathFailure::none;
  std::size_t step = 0;
  int joint = -1;
  double value = 0.0;
  std::size_t samples = 0;  ///< samples along the path (≥ 2 for a path longer than 0, 1 for a single viewpoint)
  std::string link;         ///< the colliding link (PathFailure::collision only)

  [[nodiscard]] bool ok() const { return failure == PathFailure::none; }
};

/// A check of a sampled configuration: `check(q, T_WS)` returns true if q is acceptable (no collision, ...).
template <class C>
concept ConfigurationCheck = requires(const C& c, const JointVector& q, const Pose& T_WS) {
  { c(q, T_WS) } -> std::convertible_to<bool>;
};

/// Accepts every configuration (no collision check; robot/link_collision.hpp checks the links against the voxel space).
struct AcceptAllConfigurations {
  [[nodiscard]] bool operator()(const JointVector&, const Pose&) const { return true; }
};

/// Number of samples along `path` for a step of at most `max_step_m`: ⌈length / step⌉ + 1 (1 for length 0).
[[nodiscard]] inline std::size_t scan_path_samples(const LinearScanPath& path, double max_step_m) {
  const double len = path.length();
  if (len <= 0.0) return 1;
  return static_cast<std::size_t>(std::ceil(len / max_step_m)) + 1;
}

/// Samples T_WS along `path` every ≤ `setting.max_sample_step_m` (evenly, both ends included), solves IK at sample 0
/// from `seed` and at sample i from sample i−1's solution, and stops at the first sample where IK fails, a joint
/// leaves its limits, a joint changes by more than `setting.max_joint_step` from the previous sample (not checked
/// for sample 0: reaching the start is the transfer motion's job) or `check` refuses it. Throws InvalidArgument
/// (naming the value) for an invalid setting or a seed of the wrong size or not finite. Deterministic when the
/// robot's IK is.
template <Robot R, ConfigurationCheck Check = AcceptAllConfigurations>
[[nodiscard]] ScanPathReach check_scan_path(const R& robot, const LinearScanPath& path, const JointVector& seed,
                                            const ScanPathReachSetting& setting = {}, const Check& check = {}) {
  setting.validate();
  const JointLimits limits = robot.joint_limits();
  validate_joint_vector(seed, robot.joint_count(), "check_scan_path seed");
  ScanPathReach out;
  out.samples = scan_path_samples(path, setting.max_sample_step_m);
  out.joints.reserve(out.samples);
  JointVector previous = seed;
  auto fail = [&](PathFailure f, std::size_t step, int joint, double value) {
    out.failure = f;
    out.step = step;
    out.joint = joint;
    out.value = value;
    return out;
  };
  for (std::size_t i = 0; i < out.samples; ++i) {
    const double t = out.samples == 1 ? 0.0 : static_cast<double>(i) / static_cast<double>(out.samples - 1);
    const Pose T_WS = path.pose_at(t);
    std::optional<JointVector> q = robot.ik(T_WS, previous);
    if (!q) return fail(PathFailure::unreachable, i, -1, t);
    for (Eigen::Index j = 0; j < q->size(); ++j)
      if (!((*q)[j] >= limits.lower[j] && (*q)[j] <= limits.upper[j]))
        return fail(PathFailure::joint_limit, i, static_cast<int>(j), (*q)[j]);
    if (i > 0 && q->size() > 0) {
      Eigen::Index worst = 0;
      const double jump = (*q - previous).cwiseAbs().maxCoeff(&worst);
      if (jump > setting.max_joint_step) return fail(PathFailure::joint_jump, i, static_cast<int>(worst), jump);
    }
    if (!static_cast<bool>(check(*q, T_WS))) return fail(PathFailure::configuration_rejected, i, -1, t);
    out.joints.push_back(*q);
    previous = *q;
  }
  return out;
}

/// How much of the view hemisphere over an object the robot reaches (`hemisphere_reach`).
struct HemisphereReach {
  int reachable = 0;
  int total = 0;
  [[nodiscard]] double share() const { return total > 0 ? static_cast<double>(reachable) / total : 0.0; }
};

/// Viewpoints looking at `centre` from `standoff_m` at elevations 10°, 30°, 50°, 70° (azimuths every 30°) and 90°
/// (49 in all), a viewpoint counted reachable if IK from `seed` succeeds at any of four rolls about the viewing
/// direction (0°, 90°, 180°, 270°). World frame, metres. Throws InvalidArgument for a non-finite centre, a standoff
/// not > 0 or a bad seed.
template <Robot R>
[[nodiscard]] HemisphereReach hemisphere_reach(const R& robot, const Vec3& centre, double standoff_m,
                                               const JointVector& seed) {
  validate_finite(centre, "hemisphere_reach centre");
  detail::require_positive("hemisphere_reach standoff_m", standoff_m);
  validate_joint_vector(seed, robot.joint_count(), "hemisphere_reach seed");
  HemisphereReach out;
  const double deg = std::numbers::pi / 180.0;
  for (int el = 10; el <= 90; el += 20)
    for (int az = 0; az < (el == 90 ? 1 : 360); az += 30) {
      const double e = el * deg, a = az * deg;
      const Vec3 eye = centre + standoff_m * Vec3(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
      const Pose look = Viewpoint::look_at(eye, centre, el == 90 ? Vec3::UnitX() : Vec3::UnitZ()).pose();
      bool ok = false;
      for (int roll = 0; roll < 4 && !ok; ++roll) {
        Pose T = look;
        T.linear() = look.linear() * Eigen::AngleAxisd(roll * 90.0 * deg, Vec3::UnitZ()).toRotationMatrix();
        ok = robot.ik(T, seed).has_value();
      }
      out.reachable += ok ? 1 : 0;
      ++out.total;
    }
  return out;
}

/// Refuses a set-up in which the robot cannot view the object: throws InvalidArgument naming the centre, the
/// standoff and the measured share unless `hemisphere_reach(...).share() ≥ min_share` (in (0, 1]). Call it before
/// any work (it costs 49–196 IK solves).
template <Robot R>
void require_object_in_reach(const R& robot, const Vec3& centre, double standoff_m, const JointVector& seed,
                             double min_share = 0.25) {
  detail::require(std::isfinite(min_share) && min_share > 0.0 && min_share <= 1.0,
                  "require_object_in_reach min_share must be in (0, 1], got ", min_share);
  const HemisphereReach h = hemisphere_reach(robot, centre, standoff_m, seed);
  detail::require(h.share() >= min_share, "the object at (", centre.x(), ", ", centre.y(), ", ", centre.z(),
                  ") is out of the robot's reach: ", h.reachable, " of ", h.total, " viewpoints at standoff ",
                  standoff_m, " m are reachable (", h.share(), " < min_share ", min_share,
                  "); move the robot's base or the object");
}

}  // namespace nbs
