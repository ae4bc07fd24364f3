// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The planner's utility policy (Sec. 4.5.3): scores the candidate scan paths of one planning step.
/// Built-in policies: the four thesis selections and the peer metrics (`FixedSelection<S>`, `SelectionUtility`
/// chosen at run time) and `TermUtility<Term>` for a user-defined UtilityTerm.

#include <chrono>
#include <cmath>
#include <cstdint>
#include <span>
#include <type_traits>

#include "nbs/planner/detail/components.hpp"

namespace nbs {

/// What a utility policy may depend on besides the candidates and the space. Units: none.
struct UtilityContext {
  int scans = 0;                 ///< n_s: scans integrated so far (ω(n_s), Eq. 4.31)
  std::uint64_t seed = 0;        ///< per-step seed (planner seed mixed with n_s), for Random
  const Parameters* params = nullptr;  ///< λ, n_q, incidence cut-off (never null when called by NbsPlanner)
  /// Where the sensor rests now (world, metres): the end of the last scan path (NbsPlanner); the origin before the
  /// first scan. NearestViewUtility measures from here.
  Vec3 sensor_position = Vec3::Zero();
  /// Where ĉ_m puts the missing surface after the last scan (CoverageResult::unseen: world points, m, with the area
  /// each stands for, m²); empty before the first scan or when the coverage estimator does not say. Borrowed: valid
  /// until the planner's next integrate(). SGU reads it.
  std::span<const UnseenSample> unseen_surface{};
};

/// U scores candidates: `u.evaluate(paths, sensor, space, ctx, eval)` returns one value per path and the best
/// (EvaluationResult, higher is better, ties to the lower index). Must be deterministic for any `eval.threads`.
template <class U, class Space, class Sensor>
concept UtilityPolicy = requires(const U& u, std::span<const LinearScanPath> paths, const Sensor& sensor,
                                 const Space& space, const UtilityContext& ctx, const EvaluationSetting& eval) {
  { u.evaluate(paths, sensor, space, ctx, eval) } -> std::same_as<EvaluationResult>;
};

/// One of the selection criteria of `nbs/utility/selection.hpp`, chosen at run time (Random, IG, Quality,
/// IG/Quality of Sec. 4.7, peer metrics of Delmerico et al. 2018). λ, n_q and the cut-off come from Parameters.
struct SelectionUtility {
  struct Setting {
    Selection selection = Selection::ig_quality;
    SelectionOptions options{};
  };
  Setting setting{};

  template <class Space, CandidateRaySensor Sensor>
  [[nodiscard]] EvaluationResult evaluate(std::span<const LinearScanPath> paths, const Sensor& sensor,
                                          const Space& space, const UtilityContext& ctx,
                                          const EvaluationSetting& eval) const {
    const Parameters defaults{};
    const Parameters& p = ctx.params ? *ctx.params : defaults;
    SelectionSetting s;
    s.selection = setting.selection;
    s.n_scans = ctx.scans;
    s.n_q = p.quality_half_scans;
    s.lambda = p.quality_weight;
    s.cutoff_rad = p.incidence_cutoff_rad;
    s.seed = ctx.seed;
    s.options = setting.options;
    s.unseen = ctx.unseen_surface;
    return evaluate_selection(paths, sensor, space, s, eval);
  }
};

/// A selection criterion fixed at compile time (same code path as SelectionUtility).
template <Selection S>
struct FixedSelection {
  using Setting = SelectionOptions;
  Setting setting{};

  template <class Space, CandidateRaySensor Sensor>
  [[nodiscard]] EvaluationResult evaluate(std::span<const LinearScanPath> paths, const Sensor& sensor,
                                          const Space& space, const UtilityContext& ctx,
                                          const EvaluationSetting& eval) const {
    return SelectionUtility{{S, setting}}.evaluate(paths, sensor, space, ctx, eval);
  }
};

using RandomUtility = FixedSelection<Selection::random>;              ///< R: seeded random (Sec. 4.7)
using InformationGainUtility = FixedSelection<Selection::information_gain>;  ///< I: ω = 0 in Eq. (4.30)
using QualityUtility = FixedSelection<Selection::quality>;            ///< Q: ω = 1
using IgQualityUtility = FixedSelection<Selection::ig_quality>;       ///< C: ω(n_s), Eqs. (4.30)–(4.31)
/// SGU (ours, issue 18): surface gain plus the missing surface ĉ_m locates (utility/unseen_surface.hpp); the default.
using SurfaceGainUnseenUtility = FixedSelection<Selection::surface_gain_unseen>;

/// SEE's selection (Border & Gammell; the peer method SEE): the view nearest to the sensor's current position.
/// Value of path i = −‖start_i − ctx.sensor_position‖ (metres; the sensor flies to the path's start), so the
/// evaluation's "largest value, ties to the lower index" picks the nearest, ties to the generator's order. No rays
/// are cast (`rays`, `voxels` are 0). Deterministic for any thread count.
struct NearestViewUtility {
  struct Setting {};
  Setting setting{};

  template <class Space, class Sensor>
  [[nodiscard]] EvaluationResult evaluate(std::span<const LinearScanPath> paths, const Sensor&, const Space&,
                                          const UtilityContext& ctx, const EvaluationSetting&) const {
    const auto t0 = std::chrono::steady_clock::now();
    EvaluationResult r;
    r.threads = 1;
    r.values.resize(paths.size());
    r.rays.assign(paths.size(), 0);
    r.voxels.assign(paths.size(), 0);
    r.refined.assign(paths.size(), 1);
    for (std::size_t i = 0; i < paths.size(); ++i) {
      r.values[i] = -(paths[i].start().position() - ctx.sensor_position).norm();
      if (!std::isnan(r.values[i]) && (r.best == EvaluationResult::npos || r.values[i] > r.values[r.best])) r.best = i;
    }
    r.status = paths.empty() ? EvaluationStatus::no_candidates : EvaluationStatus::ok;
    r.t_nbs_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
  }
};

/// A user-defined UtilityTerm: every candidate is scored by a copy of `setting.prototype` (evaluate_candidates).
template <UtilityTerm Term>
struct TermUtility {
  struct Setting {
    Term prototype{};
  };
  Setting setting{};

  template <class Space, CandidateRaySensor Sensor>
  [[nodiscard]] EvaluationResult evaluate(std::span<const LinearScanPath> paths, const Sensor& sensor,
                                          const Space& space, const UtilityContext&,
                                          const EvaluationSetting& eval) const {
    return evaluate_candidates(paths, sensor, space, setting.prototype, eval);
  }
};

/// A user-defined UtilityTerm built anew for each planning step by `setting.make(space, ctx)` (for terms that
/// depend on n_s, N_v, the seed, ...). `Factory` is a copyable callable returning a UtilityTerm.
template <class Factory>
struct TermFactoryUtility {
  struct Setting {
    Factory make{};
  };
  Setting setting{};

  template <class Space, CandidateRaySensor Sensor>
    requires UtilityTerm<std::invoke_result_t<const Factory&, const Space&, const UtilityContext&>>
  [[nodiscard]] EvaluationResult evaluate(std::span<const LinearScanPath> paths, const Sensor& sensor,
                                          const Space& space, const UtilityContext& ctx,
                                          const EvaluationSetting& eval) const {
    return evaluate_candidates(paths, sensor, space, setting.make(space, ctx), eval);
  }
};

}  // namespace nbs
