// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The utility of workspace modeling (Sec. 5.5): the IG part of Eq. (4.30) (ω = 0, i.e. the volumetric entropy e_v of
/// Eq. 4.32 as the planner's `Selection::information_gain` evaluates it) times the platform penalty of Eq. (5.2).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <span>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/core/scan_path.hpp"
#include "nbs/sensor/area_sensor.hpp"
#include "nbs/utility/evaluate_candidates.hpp"
#include "nbs/utility/selection.hpp"
#include "nbs/workspace/platform_pan_tilt.hpp"

namespace nbs {

/// The platform penalty of Eq. (5.2): with o_y = |s_candidate − s_current| (metres along the platform's line),
/// f_utility ← factor · (1 − o_y / max_distance_m) · f_utility if o_y > 0, unchanged if o_y = 0 (o_y ≤ 1e-9 m, the
/// rounding of grid offsets, counts as 0). Beyond the
/// maximum distance (o_y > max_distance_m) the bracket would turn negative; we clamp it at 0 (such a candidate gets
/// utility 0). Thesis values: factor 0.8, max distance 3 m.
struct PlatformPenalty {
  double factor = 0.8;          ///< in [0, 1]
  double max_distance_m = 3.0;  ///< > 0
  void validate() const {
    detail::require_in_range("PlatformPenalty.factor", factor, 0.0, 1.0);
    detail::require(std::isfinite(max_distance_m) && max_distance_m > 0.0,
                    "PlatformPenalty.max_distance_m must be finite and > 0, got ", max_distance_m);
  }
  /// The multiplier for a platform move of o_y metres (1 for o_y = 0). Throws InvalidArgument for o_y < 0 or NaN.
  [[nodiscard]] double multiplier(double o_y_m) const {
    detail::require(o_y_m >= 0.0, "PlatformPenalty: platform offset o_y must be >= 0, got ", o_y_m);
    if (o_y_m <= 1e-9) return 1.0;
    return factor * std::max(0.0, 1.0 - o_y_m / max_distance_m);
  }
  /// Eq. (5.2) applied to utility f.
  [[nodiscard]] double apply(double f, double o_y_m) const { return multiplier(o_y_m) * f; }
};

/// Per-candidate values of one workspace planning step.
struct WorkspaceEvaluation {
  std::vector<double> information_gain;  ///< e_v per candidate (Eq. 4.30 with ω = 0), bits per non-free voxel
  std::vector<double> utility;           ///< information_gain · PlatformPenalty::multiplier(o_y)
  std::size_t best = EvaluationResult::npos;  ///< largest utility; ties to the lowest index; NaN never; npos if none
  double t_plan_s = 0.0;                 ///< wall-clock time of the evaluation, seconds
};

/// Evaluates every candidate (one area-sensor frame at its T_WS) with the planner's IG criterion
/// (`evaluate_selection` with `Selection::information_gain`: Eq. 4.30, ω = 0; N_v from the space) using every
/// `downscale`-th pixel row and column (RaySampling{downscale, downscale}; the thesis plans on the range image
/// downscaled by 4), on `threads` threads (0 = hardware concurrency; values identical for any count), and applies
/// Eq. (5.2) with o_y = |platform_offset_m − current_platform_m|. Throws InvalidArgument for an invalid sensor,
/// penalty, downscale < 1 or a non-finite current platform offset.
template <VoxelSpace Space>
[[nodiscard]] WorkspaceEvaluation evaluate_workspace_candidates(std::span<const PanTiltCandidate> candidates,
                                                                const AreaSensor& sensor, const Space& space,
                                                                double current_platform_m,
                                                                const PlatformPenalty& penalty,
                                                                std::size_t downscale = 4, unsigned threads = 0) {
  const auto t0 = std::chrono::steady_clock::now();
  penalty.validate();
  detail::require(downscale >= 1, "evaluate_workspace_candidates: downscale must be >= 1, got ", downscale);
  detail::require(std::isfinite(current_platform_m),
                  "evaluate_workspace_candidates: current platform offset is not finite: ", current_platform_m);
  std::vector<LinearScanPath> paths;
  paths.reserve(candidates.size());
  for (const PanTiltCandidate& c : candidates) paths.emplace_back(Viewpoint(c.T_WS));
  SelectionSetting sel;
  sel.selection = Selection::information_gain;
  const EvaluationResult r =
      evaluate_selection(std::span<const LinearScanPath>(paths), sensor, space, sel,
                         EvaluationSetting(threads, RaySampling{downscale, downscale}));
  WorkspaceEvaluation out;
  out.information_gain = r.values;
  out.utility.resize(r.values.size());
  for (std::size_t i = 0; i < r.values.size(); ++i)
    out.utility[i] = penalty.apply(r.values[i], std::abs(candidates[i].platform_offset_m - current_platform_m));
  out.best = best_index(out.utility);
  out.t_plan_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace nbs
