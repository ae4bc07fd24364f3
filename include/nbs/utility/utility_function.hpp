// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The scalar pieces of the NBS utility, Sec. 4.5.3: ω(n_s) (Eq. 4.31), per-voxel entropy (Eq. 4.32 summand),
/// per-voxel surface quality q_i (Eq. 4.33) and the weighted utility (Eq. 4.30).

#include <cmath>

#include "nbs/core/error.hpp"

namespace nbs {

/// ω(n_s) = n_s / (n_s + n_q), Eq. (4.31): weight of the 3D-modeling part after n_s scans. n_s ≥ 0, n_q > 0.
[[nodiscard]] inline double modeling_weight(double n_scans, double n_q = 5.0) {
  detail::require_non_negative("n_scans", n_scans);
  detail::require_positive("n_q", n_q);
  return n_scans / (n_scans + n_q);
}

/// Binary entropy of one voxel with occupancy probability p, in bits: −p log₂ p − (1−p) log₂(1−p)
/// (the summand of Eq. 4.32; base 2 so an unknown voxel, p = 0.5, contributes 1). 0 for p ∈ {0, 1}.
[[nodiscard]] inline double voxel_entropy(double p) {
  detail::require_in_range("occupancy p", p, 0.0, 1.0);
  auto h = [](double q) { return q > 0.0 ? -q * std::log2(q) : 0.0; };
  return h(p) + h(1.0 - p);
}

/// Surface quality q_i of a voxel, Eq. (4.33) as the text means it: q_i = λ·(1 − b_i) + (1 − λ)·d̄_i ∈ [0, 1].
/// `border_share` b_i ∈ [0,1] (Eq. 4.28) measures *incompleteness* ("for a complete mesh no border edges should
/// exist") and `mean_density` d̄_i ∈ [0,1] (Eq. 4.26) sampling sufficiency, so a complete, densely sampled voxel has
/// q_i = 1. (Eq. 4.33 printed literally adds λ·b_i, rewarding border edges as quality; together with Eq. 4.30's
/// ω·(1 − q_s) that gives the highest modeling value to a candidate that sees no surface at all. We follow the
/// text: "the 3D modeling part chooses an NBS which views previously scanned voxels with poor mesh quality".)
[[nodiscard]] inline double voxel_quality(double border_share, double mean_density, double lambda) {
  return lambda * (1.0 - border_share) + (1.0 - lambda) * mean_density;
}

/// Modeling value of seeing voxel i with incidence angle θ: 1 − q_i if θ < `cutoff_rad` (70° in the thesis, Sec.
/// 4.5.3), else 0 ("a re-scan will not increase the quality due to the large angle of incidence").
[[nodiscard]] inline double voxel_rescan_value(double border_share, double mean_density, double incidence_rad,
                                               double lambda, double cutoff_rad) {
  return incidence_rad < cutoff_rad ? 1.0 - voxel_quality(border_share, mean_density, lambda) : 0.0;
}

/// f_utility = (1 − ω)·e_v + ω·m_s, Eq. (4.30), where m_s = Σ_i (1 − q_i) / N_v over the surface voxels the
/// candidate sees below the incidence cut-off — Eq. 4.30's "(1 − q_s)" evaluated per viewed voxel (Eq. 4.34's
/// normalisation by N_v), so a candidate that sees no surface gets no modeling value. e_v is Eq. (4.32).
[[nodiscard]] inline double weighted_utility(double entropy_ev, double modeling_ms, double omega) {
  return (1.0 - omega) * entropy_ev + omega * modeling_ms;
}

}  // namespace nbs
