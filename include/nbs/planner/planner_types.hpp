// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Results, statistics and the setting of NbsPlanner (Secs. 4.1, 4.5, 4.6). Units: SI (metres, seconds).

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "nbs/planner/detail/components.hpp"
#include "nbs/registration/registration.hpp"
#include "nbs/robot/reachability.hpp"
#include "nbs/space/block_flush.hpp"
#include "nbs/utility/ray_occluder.hpp"

namespace nbs {

/// Why next_best_scan() returned what it returned. Only `ok` carries a scan path.
enum class PlanStatus : std::uint8_t {
  ok,                ///< `path` is the next best scan
  nothing_seen_yet,  ///< the mesh has no triangle yet (Sec. 4.1): take a first scan, e.g. NbsPlanner::first_scan()
  no_candidates,     ///< every generator returned nothing (or every candidate was dropped by Alg. 3)
  done,              ///< the termination criterion holds (Sec. 4.6); no further scan is needed
  no_reachable_candidate,  ///< with a robot: candidates were left, but the robot can execute none of them
};

[[nodiscard]] constexpr std::string_view to_string(PlanStatus s) {
  switch (s) {
    case PlanStatus::ok: return "ok";
    case PlanStatus::nothing_seen_yet: return "nothing seen yet: the mesh has no triangle (take a first scan)";
    case PlanStatus::no_candidates: return "no scan candidate left (generators empty or all dropped by Alg. 3)";
    case PlanStatus::done: return "done: the termination criterion holds";
    case PlanStatus::no_reachable_candidate:
      return "no reachable candidate: the robot cannot execute the scan path of any candidate left";
  }
  return "unknown status";
}

/// What integrate() did with a scan.
enum class IntegrationStatus : std::uint8_t {
  ok,                    ///< at least one point inside the bounding box of the unknown area
  empty_scan,            ///< the scan has no point (nothing hit); the models are unchanged, n_s still counts it
  outside_unknown_area,  ///< every point lies outside the bounding box of the unknown area (Sec. 4.1); ditto
};

[[nodiscard]] constexpr std::string_view to_string(IntegrationStatus s) {
  switch (s) {
    case IntegrationStatus::ok: return "ok";
    case IntegrationStatus::empty_scan: return "empty scan: no point measured";
    case IntegrationStatus::outside_unknown_area:
      return "every point lies outside the bounding box of the unknown area";
  }
  return "unknown status";
}

[[nodiscard]] constexpr std::string_view to_string(SearchMode m) {
  return m == SearchMode::BoundarySearch ? "BS" : "HR";
}

/// Report of NbsPlanner::integrate (one per scan).
struct IntegrationReport {
  IntegrationStatus status = IntegrationStatus::ok;
  int scans = 0;                      ///< n_s after this scan
  std::size_t points = 0;             ///< points in the scan
  std::size_t points_inside = 0;      ///< of them inside the bounding box of the unknown area
  std::size_t meshed = 0;             ///< points that became mesh vertices
  std::size_t features_written = 0;   ///< voxels whose surface features were updated (Sec. 4.5.1)
  IntegrationStats space{};           ///< voxel space update counters
  double estimated_coverage = 0.0;    ///< ĉ_m after the scan, Eq. (4.35)
  double mean_density = 0.0;          ///< d̄_m after the scan, Eqs. (4.24)–(4.25)
  std::size_t holes = 0;              ///< holes found for ĉ_m (h_min ≤ |E_H| ≤ h_max)
  SearchMode mode = SearchMode::BoundarySearch;  ///< mode for the next planning step
  bool switched = false;              ///< this scan switched BS → HR (Eq. 4.38)
  bool done = false;                  ///< the termination criterion holds now
  RegistrationResult registration{};  ///< the registration step (status not_run with NoRegistration)
  double t_integrate_s = 0.0;         ///< wall-clock time of integrate(), seconds: the parts below + input checks
  double t_registration_s = 0.0;      ///< of it: input check and registration (Sec. 3.2.3)
  double t_space_s = 0.0;             ///< of it: voxel space update (Sec. 3.3.2)
  double t_mesh_s = 0.0;              ///< of it: mesh update (Sec. 3.3.1)
  double t_features_s = 0.0;          ///< of it: surface features (Sec. 4.5.1)
  double t_coverage_s = 0.0;          ///< of it: loops/holes, ĉ_m (Eqs. 4.35–4.37) and d̄_m
};

/// Statistics of one planning step (next_best_scan). Counts refer to this step.
struct IterationStats {
  int scans = 0;                      ///< n_s at planning time
  double estimated_coverage = 0.0;    ///< ĉ_m
  double mean_density = 0.0;          ///< d̄_m
  SearchMode mode = SearchMode::BoundarySearch;
  CandidateStatus generator_status = CandidateStatus::ok;  ///< of the generator run in this step (if any)
  std::size_t generated = 0;          ///< candidates the generator returned in this step
  std::size_t replanned = 0;          ///< of them rotated by Alg. 3
  std::size_t dropped = 0;            ///< of them dropped by Alg. 3 or for lying below the support plane
  std::size_t evaluated = 0;          ///< candidates in the set S that were scored
  /// With a robot (RobotReach): candidates the robot could not execute — new ones dropped by Alg. 3 because every
  /// rotation that passed occlusion and collision failed the reach check, plus candidates of S refused when chosen
  /// (re-checked from the current configuration). Included in `dropped` for the new ones. 0 without a robot.
  std::size_t unreachable = 0;
  /// Of `unreachable`, by the first failure seen for each (index: PathFailure; none stays 0).
  std::array<std::size_t, 6> unreachable_by_failure{};
  std::size_t reach_rotated = 0;      ///< new candidates whose first free rotation was unreachable but a later one not
  std::size_t reach_checks = 0;       ///< scan paths checked for reach in this step
  double best_utility = 0.0;          ///< utility of the chosen candidate (0 unless ok)
  double t_generate_s = 0.0;          ///< generation time
  double t_replan_s = 0.0;            ///< Alg. 3 time
  double t_evaluate_s = 0.0;          ///< utility evaluation time
  double t_reach_s = 0.0;             ///< reach checks (inside Alg. 3 and at selection), seconds
  double t_nbs_s = 0.0;               ///< whole next_best_scan() time (t_nbs of Tab. 4.5)
};

/// Result of NbsPlanner::next_best_scan.
struct PlanResult {
  PlanStatus status = PlanStatus::no_candidates;
  std::optional<ScanCandidate> candidate;  ///< set iff status == ok; `candidate->path` is the scan to take
  /// With a robot: the joint trajectory of `candidate->path` (check_scan_path's samples, ≤ 10 mm apart) from the
  /// current configuration; empty without a robot.
  std::vector<JointVector> joints;
  IterationStats stats{};
  [[nodiscard]] bool ok() const { return status == PlanStatus::ok && candidate.has_value(); }
  /// The scan path to take; throws InvalidArgument unless ok().
  [[nodiscard]] const LinearScanPath& path() const {
    detail::require(ok(), "PlanResult::path(): no scan path (status: ", to_string(status), ")");
    return candidate->path;
  }
};

/// Run-time knobs of NbsPlanner that are not thesis parameters (those are in Parameters).
struct PlannerSetting {
  unsigned threads = 1;            ///< candidate evaluation and scan integration threads (≥ 1); results identical for any count
  RaySampling sampling{4, 4};      ///< beam sub-sampling of the utility evaluation (every 4th profile / ray)
  ReplanSetting replan{};          ///< Alg. 3; `incidence_cutoff_rad` is overwritten by Parameters
  bool replan_candidates = true;   ///< run Alg. 3 on new candidates before they enter the set S
  double standoff_m = 0.0;         ///< d_s; 0 = middle of the sensor's working range
  std::uint64_t seed = 1;          ///< seed of Random selection (mixed with n_s per step)
  /// Our choice: when Hole Rescan has used up its candidates, detect holes again (the thesis runs on to n_abort,
  /// Sec. 4.7.2, so the second mode must keep producing candidates). If false the planner then reports no_candidates.
  bool redetect_holes = true;
  /// Our choice: when Boundary Search leaves S empty (no boundary left), switch to Hole Rescan early.
  bool rescan_when_explore_empty = true;
  /// After the switch to Hole Rescan (Eq. 4.38) keep the Boundary Search candidates and keep generating them, so S
  /// holds both and the utility chooses. The thesis (Sec. 4.4) discards them (false). Our default (true): with a
  /// noisy stream ĉ_m stalls early — on the bunny at scan 3 with c_a = 73.5 % of a possible 94.6 % — and Hole
  /// Rescan alone then gains little (nbs_diagnose: best hole candidate ≤ 5.2k new samples vs ≥ 38k for the best
  /// boundary candidate at the same step).
  bool keep_exploring = true;
  /// Coarse-to-fine evaluation of S (our addition to Sec. 4.5.3, see CoarseToFine): all candidates are scored with
  /// `sampling` strides × coarse_factor, the refine_top best again with `sampling`. Default {4, 32}: every 16th
  /// profile / ray first, then the 32 best with every 4th (≈ 1/16 + 32/|S| of the single-pass cost). bench_planner
  /// NBS_BENCH_REFINE_STUDY (seed 1, 13 steps, |S| up to 419): {4, 32} picked the single-pass candidate in 13 of 13
  /// steps; {4, 16} in 9 of 13, its worst pick within 1.6 % of the best single-pass value. {1, k} turns it off.
  CoarseToFine refine{4, 32};
  /// Flushing of cold voxel blocks to disk for spaces larger than memory (Sec. 5.5 workspace runs): off by default;
  /// applied to the space's backend when the planner is built. Plans are identical with and without it (tested);
  /// a backend that cannot flush (not FlushableBackend) refuses an enabled setting.
  BlockFlushSetting flush{};
  /// Occlusion of the simulated beams by what lies outside the unknown area (ray_occluder.hpp), e.g. the other
  /// objects of a scene (VoxelSpaceOccluder over the scene's voxel space); empty (default) = none, as in the thesis,
  /// whose planner sees only its own box. Called concurrently by the evaluation threads.
  RayOccluder occluder{};

  /// Throws InvalidArgument naming the bad field.
  void validate() const {
    detail::require(threads >= 1 && threads <= 1024, "PlannerSetting.threads must be in [1, 1024], got ", threads);
    sampling.validate();
    refine.validate();
    replan.validate();
    detail::require_non_negative("PlannerSetting.standoff_m", standoff_m);
    flush.validate("PlannerSetting.flush");
  }
};

}  // namespace nbs
