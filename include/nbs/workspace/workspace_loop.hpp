// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The NBV loop of workspace modeling (Sec. 5.5; issue 22 item 1): a mobile platform with a pan-tilt head and an
/// area sensor explores the unknown workspace box of a voxel space alone (no mesh): plan by IG with the platform
/// penalty (workspace_utility.hpp), move, take one range image, integrate it, until the free-voxel count stagnates
/// (stagnation.hpp). The collision model is exported afterwards from the space (not here).

#include <chrono>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <concepts>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/core/scan.hpp"
#include "nbs/core/scan_path.hpp"
#include "nbs/driver/concepts.hpp"
#include "nbs/planner/detail/planner_parts.hpp"
#include "nbs/recognition/hypothesis_verification.hpp"
#include "nbs/sensor/area_sensor.hpp"
#include "nbs/space/block_flush.hpp"
#include "nbs/workspace/platform_pan_tilt.hpp"
#include "nbs/workspace/stagnation.hpp"
#include "nbs/workspace/workspace_utility.hpp"

namespace nbs {

/// Everything run_workspace_modeling needs besides the space and the scan source.
struct WorkspaceSetting {
  PlatformPanTiltSetting platform;    ///< the candidates (Sec. 5.5 defaults)
  PlatformPenalty penalty;            ///< Eq. (5.2)
  StagnationSetting stop;             ///< stop rule and the max-views cap
  AreaSensor sensor;                  ///< geometry of the scan source's sensor (planning rays, update downscaling)
  std::size_t planning_downscale = 4; ///< plan with every k-th pixel row and column (thesis: 4), ≥ 1
  std::size_t update_downscale = 4;   ///< integrate every k-th pixel row and column (thesis: 4), ≥ 1
  unsigned threads = 0;               ///< candidate evaluation threads (0 = hardware); results identical for any count
  double initial_platform_m = 0.0;    ///< platform offset along the line before the first view (Eq. 5.2's reference)
  /// Block flushing of the space's backend (FlushableBackend, e.g. HashedBlockBackend); off by default. Applied
  /// before the first view, as PlannerSetting::flush (same helper).
  BlockFlushSetting flush{};
  /// With flushing off: refuse a workspace box whose worst-case memory (`worst_case_memory_bytes`, every voxel
  /// allocated) exceeds this. 0 = no check. Default 2 GiB (issue 22).
  std::uint64_t memory_limit_bytes = std::uint64_t{2} << 30;

  /// Throws InvalidArgument naming the first invalid field (its sub-settings' own messages).
  void validate() const {
    platform.validate();
    penalty.validate();
    stop.validate();
    sensor.validate();
    detail::require(planning_downscale >= 1, "WorkspaceSetting.planning_downscale must be >= 1, got ",
                    planning_downscale);
    const auto pixels = static_cast<std::size_t>(std::max(sensor.width_px, sensor.height_px));
    detail::require(planning_downscale <= pixels, "WorkspaceSetting.planning_downscale must be <= the image side ",
                    pixels, ", got ", planning_downscale);
    detail::require(update_downscale >= 1 && update_downscale <= pixels,
                    "WorkspaceSetting.update_downscale must be in [1, ", pixels, "], got ", update_downscale);
    detail::require(std::isfinite(initial_platform_m), "WorkspaceSetting.initial_platform_m is not finite: ",
                    initial_platform_m);
    flush.validate("WorkspaceSetting.flush");
  }
};

/// What one view of the loop did.
struct WorkspaceStep {
  Pose T_WS = Pose::Identity();     ///< the view's sensor pose
  std::size_t candidate = 0;        ///< index into pan_tilt_candidates(setting.platform)
  std::size_t platform_index = 0;   ///< the candidate's platform position index
  double platform_offset_m = 0.0;   ///< its offset along the line
  double platform_move_m = 0.0;     ///< o_y: |offset − previous offset|, 0 if the platform stayed
  double pan_rad = 0.0, tilt_rad = 0.0;
  double information_gain = 0.0;    ///< e_v of the chosen candidate before the penalty
  double utility = 0.0;             ///< after Eq. (5.2)
  std::uint64_t free_voxels = 0;    ///< free_voxel_count after integrating this view
  std::size_t points = 0;           ///< points the source returned
  std::size_t integrated_points = 0;///< points integrated after downscaling (beams the space accepted)
  double t_plan_s = 0.0;            ///< candidate evaluation, seconds (wall clock)
  double t_integrate_s = 0.0;       ///< downscaling + space.integrate, seconds (wall clock)
};

/// The run: one WorkspaceStep per view, why it stopped, the number of candidates.
struct WorkspaceResult {
  std::vector<WorkspaceStep> steps;
  WorkspaceStop stop = WorkspaceStop::running;
  std::size_t candidates = 0;
};

/// a · b, or UINT64_MAX where the product overflows.
[[nodiscard]] constexpr std::uint64_t mul_saturating(std::uint64_t a, std::uint64_t b) {
  return a != 0 && b > std::numeric_limits<std::uint64_t>::max() / a ? std::numeric_limits<std::uint64_t>::max() : a * b;
}

/// Upper bound of the memory the space's states take when every voxel of its unknown-area box is allocated. A
/// backend of 8³ blocks (with `Block` and `kEdge`, e.g. HashedBlockBackend): blocks touching the box ×
/// (sizeof(Block) + kEdge³ · sizeof(State) for side-cars such as ThesisState's surface evidence + 64 bytes of hash
/// node); any other backend: voxels × sizeof(State) (an estimate). Bytes, saturating at UINT64_MAX (a box of 2^21 keys per
/// axis overflows 64 bits).
template <VoxelSpace Space>
[[nodiscard]] std::uint64_t worst_case_memory_bytes(const Space& space) {
  using State = typename Space::State;
  const KeyBox box = space.bounds_keys();
  if (box.empty()) return 0;
  if constexpr (requires { typename Space::BackendType::Block; Space::BackendType::kEdge; }) {
    using B = typename Space::BackendType;
    constexpr std::int64_t edge = B::kEdge;
    std::uint64_t blocks = 1;
    for (int a = 0; a < 3; ++a) {
      const auto floor_div = [&](std::int64_t k) { return k >= 0 ? k / edge : -((-k + edge - 1) / edge); };
      blocks *= static_cast<std::uint64_t>(floor_div(box.max[a]) - floor_div(box.min[a]) + 1);  // ≤ 2^54
    }
    const std::uint64_t per_block =
        sizeof(typename B::Block) + static_cast<std::uint64_t>(edge * edge * edge) * sizeof(State) + 64;
    return mul_saturating(blocks, per_block);
  } else {
    return mul_saturating(box.volume(), sizeof(State));
  }
}

/// The area-sensor frame `scan` (one profile pose, T_WS of the frame) keeping only the points of every `factor`-th
/// pixel row and column (pixels (u, v) with u % factor = v % factor = 0: the rays append_candidate_rays keeps with
/// RaySampling{factor, factor}). A point's pixel is found by projecting it into the frame (`RangeImage::pixel_of`);
/// a point outside the image is dropped. Colours stay with their points; rays_cast becomes the kept pixel count.
/// factor 1 returns the scan unchanged. Throws InvalidArgument for factor 0, an invalid sensor or scan, or a scan
/// with other than one profile pose.
[[nodiscard]] inline Scan downscale_area_scan(const Scan& scan, const AreaSensor& sensor, std::size_t factor) {
  sensor.validate();
  detail::require(factor >= 1 && factor <= static_cast<std::size_t>(std::max(sensor.width_px, sensor.height_px)),
                  "downscale_area_scan: factor must be in [1, the image side], got ", factor);
  scan.validate();
  detail::require(scan.profile_poses.size() == 1, "downscale_area_scan: an area-sensor frame has one profile pose, "
                  "got ", scan.profile_poses.size());
  if (factor == 1) return scan;
  Scan out;
  out.profile_poses = scan.profile_poses;
  const RangeImage frame{sensor, scan.profile_poses[0], {}};
  const Pose t_sw = scan.profile_poses[0].inverse();
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const auto px = frame.pixel_of(t_sw * scan.points[i]);
    if (!px || (*px)[0] % static_cast<int>(factor) != 0 || (*px)[1] % static_cast<int>(factor) != 0) continue;
    if (scan.has_colors()) {
      out.add_point(scan.points[i], 0, scan.colors[i]);
    } else {
      out.add_point(scan.points[i], 0);
    }
  }
  const auto kept = [&](int n) { return (static_cast<std::uint64_t>(n) + factor - 1) / factor; };
  out.rays_cast = kept(sensor.width_px) * kept(sensor.height_px);
  return out;
}

/// Workspace modeling (Sec. 5.5). Before the first view: validates `setting`, builds the candidates
/// (pan_tilt_candidates), refuses (InvalidArgument, nothing changed) a box whose worst_case_memory_bytes exceeds
/// memory_limit_bytes unless flushing with a memory budget is on (in setting.flush, or already on the space's
/// backend while setting.flush is off), and applies setting.flush to the space's backend (InvalidArgument if
/// it is on and the backend is not a FlushableBackend). Then per view n = 1, 2, …:
/// 1. evaluate every candidate not taken yet (evaluate_workspace_candidates: e_v, Eq. 4.30 with ω = 0, × Eq. 5.2 relative to the
///    current platform offset, initially initial_platform_m; the first view is planned the same way, over the
///    still unknown box); pick the largest utility, ties to the lowest index; if no utility is > 0 (Eq. 5.2 is 0 from
///    max_distance_m on) take the largest IG instead; if no IG is > 0 either, stop with no_information_gain (no view
///    taken). The chosen candidate leaves the set, as in NbsPlanner:
///    taken again, its beams would be rejected by the space's beam-independence rule (Sec. 3.3.2) wherever they
///    updated it the first time, while its e_v barely drops (a voxel seen free once still has p ≈ 0.4, ≈ 0.97 bit),
///    so it would be chosen forever. No candidate left: stop with candidates_exhausted;
/// 2. `source.move_to(T_WS)`, then `source.acquire(LinearScanPath(Viewpoint(T_WS)))`: one area-sensor frame (the
///    ScanDriver contract, as run_loop drives area sensors);
/// 3. integrate downscale_area_scan(scan, setting.sensor, update_downscale) into the space; count the free voxels;
///    record a WorkspaceStep; the platform is now at the candidate's offset;
/// 4. stop if stagnation_check(counts, setting.stop) fires.
/// Deterministic: the same space, source and setting give the same steps for any thread count. An exception of the
/// source or the space propagates (steps so far are lost; the space holds the views integrated before).
/// `source` is any ScanDriver: hardware, a `SimulatedDriver` over a ScanSimulator for AreaSensor, a replay.
/// `on_step(step)` is called on the calling thread after each view is integrated and recorded (progress output, a
/// checkpoint of the space); what it throws propagates as the source's exceptions do.
template <VoxelSpace Space, ScanDriver Source, std::invocable<const WorkspaceStep&> OnStep>
WorkspaceResult run_workspace_modeling(Space& space, Source& source, const WorkspaceSetting& setting,
                                       OnStep&& on_step) {
  setting.validate();
  const std::vector<PanTiltCandidate> candidates = pan_tilt_candidates(setting.platform);
  // Bounded memory needs a memory budget (idle_scans alone does not bound it), set here or on the space already.
  bool budget = setting.flush.enabled() && setting.flush.memory_budget_bytes > 0;
  if constexpr (detail::FlushableSpace<Space>) {
    const BlockFlushSetting& current = space.backend().flush_policy();
    budget = budget || (!setting.flush.enabled() && current.enabled() && current.memory_budget_bytes > 0);
  }
  if (!budget && setting.memory_limit_bytes > 0) {
    const std::uint64_t need = worst_case_memory_bytes(space);
    const bool saturated = need == std::numeric_limits<std::uint64_t>::max();
    detail::require(!saturated && need <= setting.memory_limit_bytes,
                    "run_workspace_modeling: the workspace box needs up to ",
                    saturated ? std::string("more than 2^64") : std::to_string(need),
                    " bytes with every voxel allocated, more than WorkspaceSetting.memory_limit_bytes = ",
                    setting.memory_limit_bytes, "; switch on block flushing with a memory budget "
                    "(WorkspaceSetting.flush.memory_budget_bytes), use coarser voxels or a smaller box");
  }
  if constexpr (!detail::FlushableSpace<Space>) {
    detail::require(!setting.flush.enabled(), "WorkspaceSetting.flush: the voxel space cannot flush blocks to disk "
                    "(its backend is not a FlushableBackend, e.g. HashedBlockBackend)");
  }
  detail::apply_flush_setting(space, setting.flush);

  WorkspaceResult result;
  result.candidates = candidates.size();
  std::vector<std::uint64_t> counts;
  std::vector<std::size_t> open(candidates.size());  // indices of the candidates not taken yet, ascending
  for (std::size_t i = 0; i < open.size(); ++i) open[i] = i;
  std::vector<PanTiltCandidate> open_candidates = candidates;
  double platform_m = setting.initial_platform_m;
  while (result.stop == WorkspaceStop::running) {
    if (open.empty()) {
      result.stop = WorkspaceStop::candidates_exhausted;
      break;
    }
    const WorkspaceEvaluation eval =
        evaluate_workspace_candidates(std::span<const PanTiltCandidate>(open_candidates), setting.sensor, space,
                                      platform_m, setting.penalty, setting.planning_downscale, setting.threads);
    std::size_t pick = eval.best;
    if (pick == EvaluationResult::npos || !(eval.utility[pick] > 0.0)) {
      // Eq. 5.2 is 0 from max_distance_m on: while a candidate still has information gain, take the largest
      // (ties: lowest index) rather than stopping with space left to explore.
      pick = EvaluationResult::npos;
      double best = 0.0;
      for (std::size_t i = 0; i < eval.information_gain.size(); ++i)
        if (eval.information_gain[i] > best) {
          best = eval.information_gain[i];
          pick = i;
        }
      if (pick == EvaluationResult::npos) {
        result.stop = WorkspaceStop::no_information_gain;
        break;
      }
    }
    const std::size_t chosen = open[pick];
    const PanTiltCandidate c = candidates[chosen];
    open.erase(open.begin() + static_cast<std::ptrdiff_t>(pick));
    open_candidates.erase(open_candidates.begin() + static_cast<std::ptrdiff_t>(pick));
    source.move_to(c.T_WS);
    const Scan scan = source.acquire(LinearScanPath(Viewpoint(c.T_WS)));
    const auto t0 = std::chrono::steady_clock::now();
    const Scan down = downscale_area_scan(scan, setting.sensor, setting.update_downscale);
    const IntegrationStats st = integrate_scan(space, down, setting.threads);
    const double t_integrate = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    WorkspaceStep step;
    step.T_WS = c.T_WS;
    step.candidate = chosen;
    step.platform_index = c.platform_index;
    step.platform_offset_m = c.platform_offset_m;
    step.platform_move_m = std::abs(c.platform_offset_m - platform_m);
    step.pan_rad = c.pan_rad;
    step.tilt_rad = c.tilt_rad;
    step.information_gain = eval.information_gain[pick];
    step.utility = eval.utility[pick];
    step.free_voxels = free_voxel_count(space, setting.stop.free_below);
    step.points = scan.size();
    step.integrated_points = st.integrated;
    step.t_plan_s = eval.t_plan_s;
    step.t_integrate_s = t_integrate;
    platform_m = c.platform_offset_m;
    counts.push_back(step.free_voxels);
    result.steps.push_back(step);
    on_step(result.steps.back());
    result.stop = stagnation_check(counts, setting.stop);
  }
  return result;
}

/// run_workspace_modeling without a per-view callback.
template <VoxelSpace Space, ScanDriver Source>
WorkspaceResult run_workspace_modeling(Space& space, Source& source, const WorkspaceSetting& setting) {
  return run_workspace_modeling(space, source, setting, [](const WorkspaceStep&) {});
}

}  // namespace nbs
