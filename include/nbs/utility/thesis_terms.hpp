// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The utility terms of the thesis (Sec. 4.5.3): volumetric entropy e_v (Eq. 4.32), surface quality q_s
/// (Eqs. 4.33–4.34), the weighted utility f_utility (Eq. 4.30) and seeded random selection (Sec. 4.7).
/// All of them count a voxel once per candidate by default (Sec. 4.5.3, `VoxelVisit::first_visit`).

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>

#include "nbs/core/error.hpp"
#include "nbs/core/detail/random.hpp"
#include "nbs/utility/utility_function.hpp"
#include "nbs/utility/utility_term.hpp"

namespace nbs {

/// Incidence angle θ ∈ [0, π] (radians) between a simulated ray (unit `direction`) and a voxel's mean normal n̄_i
/// (Sec. 4.5.3): θ = acos(⟨−r_s, n̄_i⟩ / |n̄_i|), so a ray hitting a surface head-on (n̄ facing the sensor) has θ = 0 and
/// a back-facing normal has θ > 90°. π if |n̄_i| is 0 or not finite (no usable normal).
[[nodiscard]] inline double incidence_angle_rad(const Vec3& direction, const Eigen::Vector3f& mean_normal) {
  const Vec3 n = mean_normal.cast<double>();
  const double len = n.norm();
  if (!(len > 0.0) || !std::isfinite(len)) return std::numbers::pi;
  return std::acos(std::clamp(-direction.dot(n) / len, -1.0, 1.0));
}

/// Volumetric entropy e_v of a candidate, Eq. (4.32): the binary entropy (bits, `voxel_entropy`) of every voxel a
/// beam crosses up to and including the first occupied one, summed and divided by N_v, the number of non-free
/// voxels in the space (see `non_free_voxel_count`).
class VolumetricEntropy {
public:
  struct Setting {
    double non_free_voxels = 1.0;  ///< N_v > 0
    bool count_once = true;        ///< count each voxel once per candidate (Sec. 4.5.3)
    void validate() const { detail::require_positive("VolumetricEntropy.non_free_voxels", non_free_voxels); }
  };
  VolumetricEntropy() = default;
  explicit VolumetricEntropy(const Setting& s) : setting_(s) { s.validate(); }

  void begin_candidate(std::size_t) { sum_ = 0.0; }
  void begin_ray() {}
  void visit(const VoxelVisit& v) {
    if (v.first_visit || !setting_.count_once) sum_ += v.entropy();
  }
  void end_ray(const RayEnd&) {}
  /// True with count_once: visit() ignores repeated visits (visits_first_only).
  [[nodiscard]] bool first_visits_only() const { return setting_.count_once; }
  /// e_v (bits per non-free voxel).
  [[nodiscard]] double value() const { return sum_ / setting_.non_free_voxels; }
  /// The unnormalised sum Σ H(p_i) in bits.
  [[nodiscard]] double sum() const { return sum_; }
  [[nodiscard]] const Setting& setting() const { return setting_; }

private:
  Setting setting_;
  double sum_ = 0.0;
};

/// Surface-quality (modeling) part m_s of a candidate, Eqs. (4.33)–(4.34): Σ (1 − q_i) / N_v over the crossed
/// voxels that carry surface features and are seen with incidence θ (`incidence_angle_rad`) below the cut-off, with
/// q_i = λ·(1 − b_i) + (1 − λ)·d̄_i (see `voxel_quality` for why b_i enters as 1 − b_i). High m_s: the candidate
/// re-scans incomplete or sparsely sampled surface.
class SurfaceQuality {
public:
  struct Setting {
    double non_free_voxels = 1.0;                          ///< N_v > 0
    double lambda = 0.7;                                   ///< λ ∈ [0, 1] (Tab. 4.3)
    double cutoff_rad = 70.0 * std::numbers::pi / 180.0;   ///< incidence cut-off (70°, Sec. 4.5.3)
    bool count_once = true;                                ///< count each voxel once per candidate (Sec. 4.5.3)
    void validate() const {
      detail::require_positive("SurfaceQuality.non_free_voxels", non_free_voxels);
      detail::require_in_range("SurfaceQuality.lambda", lambda, 0.0, 1.0);
      detail::require_in_range("SurfaceQuality.cutoff_rad", cutoff_rad, 0.0, std::numbers::pi);
    }
  };
  SurfaceQuality() = default;
  explicit SurfaceQuality(const Setting& s) : setting_(s) { s.validate(); }

  void begin_candidate(std::size_t) { sum_ = 0.0; }
  void begin_ray() {}
  void visit(const VoxelVisit& v) {
    if (v.features == nullptr || !(v.first_visit || !setting_.count_once)) return;
    const SurfaceFeatures& f = *v.features;
    sum_ += voxel_rescan_value(f.border_share, f.mean_density, incidence_angle_rad(v.direction, f.mean_normal),
                               setting_.lambda, setting_.cutoff_rad);
  }
  void end_ray(const RayEnd&) {}
  /// True with count_once: visit() ignores repeated visits (visits_first_only).
  [[nodiscard]] bool first_visits_only() const { return setting_.count_once; }
  /// m_s = Σ (1 − q_i) / N_v (Eq. 4.34 normalisation).
  [[nodiscard]] double value() const { return sum_ / setting_.non_free_voxels; }
  /// The unnormalised sum Σ (1 − q_i).
  [[nodiscard]] double sum() const { return sum_; }
  [[nodiscard]] const Setting& setting() const { return setting_; }

private:
  Setting setting_;
  double sum_ = 0.0;
};

/// f_utility = (1 − ω)·e_v + ω·m_s, Eq. (4.30) (see `weighted_utility`), from one cast feeding e_v and m_s.
/// ω = ω(n_s) of Eq. (4.31) for the thesis's IG/Quality selection; ω = 0 gives IG and ω = 1 Quality (Sec. 4.7).
class WeightedUtility {
public:
  struct Setting {
    double non_free_voxels = 1.0;                          ///< N_v > 0
    double omega = 0.0;                                    ///< ω ∈ [0, 1]
    double lambda = 0.7;                                   ///< λ of Eq. (4.33)
    double cutoff_rad = 70.0 * std::numbers::pi / 180.0;   ///< incidence cut-off of Eq. (4.33)
    bool count_once = true;                                ///< Sec. 4.5.3
    void validate() const { detail::require_in_range("WeightedUtility.omega", omega, 0.0, 1.0); }
  };
  WeightedUtility() = default;
  explicit WeightedUtility(const Setting& s)
      : omega_(s.omega),
        terms_(VolumetricEntropy({s.non_free_voxels, s.count_once}),
               SurfaceQuality({s.non_free_voxels, s.lambda, s.cutoff_rad, s.count_once})) {
    s.validate();
  }
  /// ω = ω(n_s) of Eq. (4.31) after `n_scans` scans with n_q (5 in the thesis).
  [[nodiscard]] static Setting thesis(double non_free_voxels, double n_scans, double n_q = 5.0) {
    Setting s;
    s.non_free_voxels = non_free_voxels;
    s.omega = modeling_weight(n_scans, n_q);
    return s;
  }

  void begin_candidate(std::size_t i) { terms_.begin_candidate(i); }
  void begin_ray() { terms_.begin_ray(); }
  void visit(const VoxelVisit& v) { terms_.visit(v); }
  void end_ray(const RayEnd& e) { terms_.end_ray(e); }
  [[nodiscard]] double value() const { return weighted_utility(entropy(), modeling(), omega_); }
  /// True with count_once (visits_first_only).
  [[nodiscard]] bool first_visits_only() const { return terms_.first_visits_only(); }
  [[nodiscard]] double entropy() const { return terms_.get<0>().value(); }  ///< e_v, Eq. (4.32)
  [[nodiscard]] double modeling() const { return terms_.get<1>().value(); }  ///< m_s = Σ(1 − q_i)/N_v, Eq. (4.34)
  [[nodiscard]] double omega() const { return omega_; }

private:
  double omega_ = 0.0;
  TermSet<VolumetricEntropy, SurfaceQuality> terms_;
};

/// Random selection (Sec. 4.7): candidate i gets a value uniform in [0, 1) derived from (seed, i) only, so the
/// choice is the same for any thread count and evaluation order. Needs no ray casts.
class RandomSelection {
public:
  static constexpr bool kNeedsRays = false;
  struct Setting {
    std::uint64_t seed = 0;
  };
  RandomSelection() = default;
  explicit RandomSelection(const Setting& s) : setting_(s) {}

  void begin_candidate(std::size_t i) {
    const std::uint64_t h = detail::splitmix64(setting_.seed ^ detail::splitmix64(static_cast<std::uint64_t>(i)));
    value_ = static_cast<double>(h >> 11) * 0x1.0p-53;
  }
  void begin_ray() {}
  void visit(const VoxelVisit&) {}
  void end_ray(const RayEnd&) {}
  [[nodiscard]] double value() const { return value_; }

private:
  Setting setting_;
  double value_ = 0.0;
};

static_assert(UtilityTerm<VolumetricEntropy> && UtilityTerm<SurfaceQuality> && UtilityTerm<WeightedUtility> &&
              UtilityTerm<RandomSelection>);

}  // namespace nbs
