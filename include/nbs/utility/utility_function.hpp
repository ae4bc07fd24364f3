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

/// Surface quality q_i of a voxel, Eq. (4.33): λ·b_i + (1−λ)·d̄_i if the incidence angle θ between the simulated
/// ray and the voxel's mean normal is below `cutoff_rad` (70° in the thesis), else 0.
/// `border_share` b_i ∈ [0,1] (Eq. 4.28), `mean_density` d̄_i ∈ [0,1] (Eq. 4.26), `incidence_rad` θ ∈ [0, π].
[[nodiscard]] inline double voxel_quality(double border_share, double mean_density, double incidence_rad,
                                          double lambda, double cutoff_rad) {
  return incidence_rad < cutoff_rad ? lambda * border_share + (1.0 - lambda) * mean_density : 0.0;
}

/// f_utility = (1 − ω)·e_v + ω·(1 − q_s), Eq. (4.30). e_v (Eq. 4.32) and q_s (Eq. 4.34) are already normalised by
/// the number of non-free voxels N_v.
[[nodiscard]] inline double weighted_utility(double entropy_ev, double quality_qs, double omega) {
  return (1.0 - omega) * entropy_ev + omega * (1.0 - quality_qs);
}

}  // namespace nbs
