// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Surface gain SG (ours; issue 18, docs/evaluation.md "Surface gain"): the rear-side entropy of Delmerico et al.
/// (2018, `RearSideEntropyVI`) per non-free voxel, divided by the candidate's scan path length:
///
///   f_SG(i) = [g_rs(i)/N_v] / (l_i + l_0)                             (the default)
///   f_SG(i) = [(1 − ω)·g_rs(i)/N_v + ω·m_s(i)] / (l_i + l_0)          (`modeling`: Eq. 4.30 with e_v replaced)
///   f_SGU(i) = [(g_rs(i) + β·g_u(i))/N_v] / (l_i + l_0)               (`unseen_weight` β > 0 and an unseen map)
///
/// and without the division when no lengths are given.
/// - g_u: the unseen-surface gain (nbs/utility/unseen_surface.hpp), the area of ĉ_m's missing surface the beams
///   reach, in voxel faces; β converts it to bits of g_rs.
/// - g_rs: Σ over rays of P_v·H(x) of the unobserved voxels directly in front of an occupied one (bits), i.e. the
///   unknown space a view would resolve next to surface already measured. e_v (Eq. 4.32) also counts the unknown
///   space far from any surface that long beams cross; it made IG/Quality prefer such views (nbs_diagnose).
/// - m_s, ω = ω(n_s), λ and the incidence cut-off exactly as in Eqs. 4.31, 4.33–4.34 (`SurfaceQuality`). The first
///   SG evaluation used this form; on the training meshes the modeling term cost scans in the tail (spot k99 12.5
///   against 10 without it, runs 0–5), so it is off by default.
/// - l_i = |s_p^2 − s_p^1| of candidate i (metres), l_0 > 0 (metres): gain per metre of scan path, so a short Hole
///   Rescan path (Sec. 4.4) wins over a long Boundary Search path of similar gain.

#include <cmath>
#include <cstddef>
#include <numbers>
#include <span>

#include "nbs/core/error.hpp"
#include "nbs/utility/peer_terms.hpp"
#include "nbs/utility/thesis_terms.hpp"
#include "nbs/utility/unseen_surface.hpp"

namespace nbs {

class SurfaceGain {
public:
  struct Setting {
    double non_free_voxels = 1.0;                          ///< N_v > 0
    double omega = 0.0;                                    ///< ω ∈ [0, 1] (ω(n_s) of Eq. 4.31 in the planner)
    double lambda = 0.7;                                   ///< λ of Eq. (4.33)
    double cutoff_rad = 70.0 * std::numbers::pi / 180.0;   ///< incidence cut-off of Eq. (4.33)
    double length_offset_m = 0.05;                         ///< l_0 > 0 of the per-metre form
    bool modeling = false;                                 ///< add ω·m_s (Eq. 4.30's 3D modeling part), see above
    double unseen_weight = 0.0;                            ///< β ≥ 0 of f_SGU (0: g_u is not evaluated)
    void validate() const {
      detail::require_positive("SurfaceGain.non_free_voxels", non_free_voxels);
      detail::require_in_range("SurfaceGain.omega", omega, 0.0, 1.0);
      detail::require_positive("SurfaceGain.length_offset_m", length_offset_m);
      detail::require(std::isfinite(unseen_weight) && unseen_weight >= 0.0,
                      "SurfaceGain.unseen_weight must be finite and >= 0, got ", unseen_weight);
    }
  };
  SurfaceGain() = default;
  /// `lengths_m[i]` = scan path length of candidate i (metres, finite, ≥ 0), borrowed for the term's lifetime;
  /// empty = no per-metre division. `unseen` (borrowed; null = none) feeds g_u when unseen_weight > 0.
  explicit SurfaceGain(const Setting& s, std::span<const double> lengths_m = {},
                       const UnseenSurfaceMap* unseen = nullptr)
      : setting_(s),
        lengths_m_(lengths_m),
        terms_(RearSideEntropyVI(), SurfaceQuality({s.non_free_voxels, s.lambda, s.cutoff_rad, true}),
               UnseenSurfaceVI(s.unseen_weight > 0.0 && unseen != nullptr ? unseen : nullptr)) {
    s.validate();
    for (double l : lengths_m)
      detail::require(std::isfinite(l) && l >= 0.0, "SurfaceGain: scan path length must be finite and >= 0, got ", l);
  }

  void begin_candidate(std::size_t i) {
    detail::require(lengths_m_.empty() || i < lengths_m_.size(), "SurfaceGain: candidate ", i, " has no length (",
                    lengths_m_.size(), " given)");
    candidate_ = i;
    terms_.begin_candidate(i);
  }
  void begin_ray() { terms_.begin_ray(); }
  void visit(const VoxelVisit& v) { terms_.visit(v); }
  void end_ray(const RayEnd& e) { terms_.end_ray(e); }
  [[nodiscard]] double value() const {
    const double g = setting_.unseen_weight > 0.0 ? rear_side_entropy() + setting_.unseen_weight * unseen_gain()
                                                  : rear_side_entropy();
    const double f = weighted_utility(g, modeling(), setting_.modeling ? setting_.omega : 0.0);
    return lengths_m_.empty() ? f : f / (lengths_m_[candidate_] + setting_.length_offset_m);
  }
  /// g_rs / N_v (bits per non-free voxel).
  [[nodiscard]] double rear_side_entropy() const { return terms_.get<0>().value() / setting_.non_free_voxels; }
  [[nodiscard]] double modeling() const { return terms_.get<1>().value(); }  ///< m_s, Eq. (4.34)
  /// g_u / N_v (voxel faces of unseen surface per non-free voxel); 0 without an unseen map or with β = 0.
  [[nodiscard]] double unseen_gain() const { return terms_.get<2>().value() / setting_.non_free_voxels; }
  [[nodiscard]] const Setting& setting() const { return setting_; }

private:
  Setting setting_;
  std::span<const double> lengths_m_;
  std::size_t candidate_ = 0;
  TermSet<RearSideEntropyVI, SurfaceQuality, UnseenSurfaceVI> terms_;
};

static_assert(UtilityTerm<SurfaceGain>);

}  // namespace nbs
