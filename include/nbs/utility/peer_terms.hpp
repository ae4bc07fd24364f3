// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Volumetric information (VI) metrics compared by Delmerico, Isler, Sabzevari, Scaramuzza, "A comparison of
/// volumetric information gain metrics for active 3D object reconstruction", Autonomous Robots 42(2), 2018
/// (after Isler et al., ICRA 2016), as utility terms, for side-by-side comparison with the thesis's utility.
///
/// Common definitions (per ray, voxels x_0, x_1, … in order from the sensor, up to the first occupied one):
/// - I(x) = −P_o ln P_o − (1 − P_o) ln(1 − P_o), the voxel entropy. We use bits (`voxel_entropy`); this scales every
///   entropy-based VI by 1/ln 2 and changes no ranking.
/// - P_v(x_n) = ∏_{i<n} (1 − P_o(x_i)), the visibility likelihood (the paper's definition; the authors' code
///   multiplies P_o instead, see uzh-rpg/rpg_ig_active_reconstruction issue #9).
/// - I_o(x) = P_v(x)·I(x), the occlusion-aware VI of a voxel.
/// - "unobserved": never updated by a scan (`VoxelVisit::observed` false).
/// The gain of a view is the sum of the per-voxel VI over all its rays. The paper counts a voxel once per ray that
/// crosses it, hence `count_once = false` by default; `true` applies Sec. 4.5.3's visited marking instead.

#include <cstddef>
#include <cstdint>

#include "nbs/core/error.hpp"
#include "nbs/utility/proximity_field.hpp"
#include "nbs/utility/utility_function.hpp"
#include "nbs/utility/utility_term.hpp"

namespace nbs {

/// Shared setting of the peer terms.
struct PeerTermSetting {
  bool count_once = false;  ///< count a voxel only on its first visit for the candidate (Sec. 4.5.3)
};

namespace detail {
/// Per-ray visibility bookkeeping shared by the P_v-weighted terms.
struct Visibility {
  double p_vis = 1.0;
  void reset() { p_vis = 1.0; }
  /// Returns P_v(x) for the current voxel and advances past it.
  double advance(double p_occ) {
    const double pv = p_vis;
    p_vis *= 1.0 - p_occ;
    return pv;
  }
};
}  // namespace detail

/// Occlusion-aware VI: G = Σ_x I_o(x) = Σ_x P_v(x)·I(x).
class OcclusionAwareVI {
public:
  OcclusionAwareVI() = default;
  explicit OcclusionAwareVI(const PeerTermSetting& s) : setting_(s) {}
  void begin_candidate(std::size_t) { sum_ = 0.0; }
  void begin_ray() { vis_.reset(); }
  void visit(const VoxelVisit& v) {
    const double pv = vis_.advance(v.probability);
    if (v.first_visit || !setting_.count_once) sum_ += pv * v.entropy();
  }
  void end_ray(const RayEnd&) {}
  [[nodiscard]] double value() const { return sum_; }

private:
  PeerTermSetting setting_;
  detail::Visibility vis_;
  double sum_ = 0.0;
};

/// Unobserved-voxel VI: I_u(x) = I_o(x) if x is unobserved, else 0.
class UnobservedVoxelVI {
public:
  UnobservedVoxelVI() = default;
  explicit UnobservedVoxelVI(const PeerTermSetting& s) : setting_(s) {}
  void begin_candidate(std::size_t) { sum_ = 0.0; }
  void begin_ray() { vis_.reset(); }
  void visit(const VoxelVisit& v) {
    const double pv = vis_.advance(v.probability);
    if (!v.observed && (v.first_visit || !setting_.count_once)) sum_ += pv * v.entropy();
  }
  void end_ray(const RayEnd&) {}
  [[nodiscard]] double value() const { return sum_; }

private:
  PeerTermSetting setting_;
  detail::Visibility vis_;
  double sum_ = 0.0;
};

/// Rear-side-voxel VI: I_b(x) = 1 for every rear side, i.e. a ray that reaches an occupied voxel directly from an
/// unobserved one (it looks at the back of an observed surface, where unknown space is expected); G counts them.
/// With count_once, each occupied voxel is counted at most once per candidate.
class RearSideVoxelVI {
public:
  RearSideVoxelVI() = default;
  explicit RearSideVoxelVI(const PeerTermSetting& s) : setting_(s) {}
  void begin_candidate(std::size_t) { count_ = 0; }
  void begin_ray() { previous_unobserved_ = false; }
  void visit(const VoxelVisit& v) {
    if (v.occupied && previous_unobserved_ && (v.first_visit || !setting_.count_once)) ++count_;
    previous_unobserved_ = !v.observed;
  }
  void end_ray(const RayEnd&) {}
  [[nodiscard]] double value() const { return static_cast<double>(count_); }

private:
  PeerTermSetting setting_;
  bool previous_unobserved_ = false;
  std::uint64_t count_ = 0;
};

/// Rear-side-entropy VI: I_n(x) = I_o(x) for the unobserved voxels of the run directly in front of a rear side
/// (the contiguous unobserved voxels a ray crosses just before it reaches an occupied voxel), else 0. The authors'
/// code also adds I_o of the occupied voxel itself; we follow the paper's per-voxel definition.
class RearSideEntropyVI {
public:
  RearSideEntropyVI() = default;
  explicit RearSideEntropyVI(const PeerTermSetting& s) : setting_(s) {}
  void begin_candidate(std::size_t) { sum_ = 0.0; }
  void begin_ray() {
    vis_.reset();
    run_ = 0.0;
  }
  void visit(const VoxelVisit& v) {
    const double pv = vis_.advance(v.probability);
    if (v.occupied) {
      sum_ += run_;
      run_ = 0.0;
    } else if (!v.observed) {
      if (v.first_visit || !setting_.count_once) run_ += pv * v.entropy();
    } else {
      run_ = 0.0;
    }
  }
  void end_ray(const RayEnd&) {}
  [[nodiscard]] double value() const { return sum_; }

private:
  PeerTermSetting setting_;
  detail::Visibility vis_;
  double run_ = 0.0;
  double sum_ = 0.0;
};

/// Proximity-count VI: I_k(x) = d_max − d(x) for an unobserved voxel x within d_max of the observed surface
/// (d(x) from a `ProximityField`), else 0. The field must outlive the term.
class ProximityCountVI {
public:
  ProximityCountVI() = default;
  explicit ProximityCountVI(const ProximityField& field, const PeerTermSetting& s = {}) : field_(&field), setting_(s) {}
  void begin_candidate(std::size_t) {
    detail::require(field_ != nullptr, "ProximityCountVI: no ProximityField given");
    sum_ = 0.0;
  }
  void begin_ray() {}
  void visit(const VoxelVisit& v) {
    if (v.observed || !(v.first_visit || !setting_.count_once)) return;
    const double d = field_->distance_m(v.key);
    if (d >= 0.0) sum_ += field_->d_max_m() - d;
  }
  void end_ray(const RayEnd&) {}
  [[nodiscard]] double value() const { return sum_; }

private:
  const ProximityField* field_ = nullptr;
  PeerTermSetting setting_;
  double sum_ = 0.0;
};

/// Average-entropy VI (the paper's rendering of Kriegel et al. 2015): G = Σ_x I(x) / |X|, the mean entropy of the
/// voxels X traversed by the view's rays. 0 if no voxel was traversed. The authors' code averages only over rays
/// that end on an occupied voxel; set `hit_rays_only` for that reading.
class AverageEntropyVI {
public:
  struct Setting {
    bool count_once = false;
    bool hit_rays_only = false;
  };
  AverageEntropyVI() = default;
  explicit AverageEntropyVI(const Setting& s) : setting_(s) {}
  void begin_candidate(std::size_t) {
    sum_ = 0.0;
    count_ = 0;
  }
  void begin_ray() {
    ray_sum_ = 0.0;
    ray_count_ = 0;
  }
  void visit(const VoxelVisit& v) {
    if (!(v.first_visit || !setting_.count_once)) return;
    ray_sum_ += v.entropy();
    ++ray_count_;
  }
  void end_ray(const RayEnd& e) {
    if (setting_.hit_rays_only && !e.hit) return;
    sum_ += ray_sum_;
    count_ += ray_count_;
  }
  [[nodiscard]] double value() const { return count_ == 0 ? 0.0 : sum_ / static_cast<double>(count_); }

private:
  Setting setting_;
  double sum_ = 0.0, ray_sum_ = 0.0;
  std::uint64_t count_ = 0, ray_count_ = 0;
};

/// The area factor of Vasquez-Gomez et al. (2014) as used by Delmerico et al. (2018): f(x; α) = −2x³/α³ + 3x²/α² for
/// x ≤ α and f(x; α) = (−2x³ + 3(α+1)x² − 6αx + 3α − 1)/(α − 1)³ for x > α; f(0) = 0, f(α) = 1 (the desired
/// share), f(1) = 0. α ∈ (0, 1), x ∈ [0, 1].
[[nodiscard]] inline double vasquez_gomez_area_factor(double x, double alpha) {
  detail::require(alpha > 0.0 && alpha < 1.0, "area factor alpha must be in (0, 1), got ", alpha);
  if (x <= alpha) return x * x * (3.0 / (alpha * alpha) - 2.0 * x / (alpha * alpha * alpha));
  const double a1 = alpha - 1.0, a13 = a1 * a1 * a1;
  return (-2.0 * x * x * x + 3.0 * (alpha + 1.0) * x * x - 6.0 * alpha * x + 3.0 * alpha - 1.0) / a13;
}

/// Vasquez-Gomez area-factor VI. Each ray is classified once, by the first event on it:
/// - an unobserved voxel in the proximity field (the "occplane", unknown space next to the surface) → occplane;
/// - an occupied voxel reached from an observed free voxel, or as the first voxel of the ray → occupied
///   (one reached from an unobserved voxel is seen from behind and is not counted at all);
/// - neither by the end of the ray → unobserved.
/// G = f(n_occupied / n, α_oc) + f(n_occplane / n, α_op) with n the number of counted rays (0 if none).
class VasquezGomezVI {
public:
  struct Setting {
    double alpha_occupied = 0.2;  ///< desired share of occupied rays (reference implementation default)
    double alpha_occplane = 0.8;  ///< desired share of occplane rays (reference implementation default)
  };
  VasquezGomezVI() = default;
  explicit VasquezGomezVI(const ProximityField& field) : VasquezGomezVI(field, Setting{}) {}
  VasquezGomezVI(const ProximityField& field, const Setting& s) : field_(&field), setting_(s) {
    detail::require(s.alpha_occupied > 0.0 && s.alpha_occupied < 1.0 && s.alpha_occplane > 0.0 &&
                        s.alpha_occplane < 1.0,
                    "VasquezGomezVI: alphas must be in (0, 1), got ", s.alpha_occupied, ", ", s.alpha_occplane);
  }
  void begin_candidate(std::size_t) {
    detail::require(field_ != nullptr, "VasquezGomezVI: no ProximityField given");
    occupied_ = occplane_ = unobserved_ = 0;
  }
  void begin_ray() {
    registered_ = false;
    previous_free_ = true;
  }
  void visit(const VoxelVisit& v) {
    if (registered_) return;
    if (!v.observed && field_->distance_m(v.key) >= 0.0) {
      ++occplane_;
      registered_ = true;
    } else if (v.occupied) {
      if (previous_free_) ++occupied_;
      registered_ = true;
    } else {
      previous_free_ = v.observed;
    }
  }
  void end_ray(const RayEnd&) {
    if (!registered_) ++unobserved_;
  }
  [[nodiscard]] double value() const {
    const double n = static_cast<double>(occupied_ + occplane_ + unobserved_);
    if (n == 0.0) return 0.0;
    return vasquez_gomez_area_factor(static_cast<double>(occupied_) / n, setting_.alpha_occupied) +
           vasquez_gomez_area_factor(static_cast<double>(occplane_) / n, setting_.alpha_occplane);
  }
  [[nodiscard]] std::uint64_t occupied_rays() const { return occupied_; }
  [[nodiscard]] std::uint64_t occplane_rays() const { return occplane_; }
  [[nodiscard]] std::uint64_t unobserved_rays() const { return unobserved_; }

private:
  const ProximityField* field_ = nullptr;
  Setting setting_;
  bool registered_ = false, previous_free_ = true;
  std::uint64_t occupied_ = 0, occplane_ = 0, unobserved_ = 0;
};

static_assert(UtilityTerm<OcclusionAwareVI> && UtilityTerm<UnobservedVoxelVI> && UtilityTerm<RearSideVoxelVI> &&
              UtilityTerm<RearSideEntropyVI> && UtilityTerm<ProximityCountVI> && UtilityTerm<AverageEntropyVI> &&
              UtilityTerm<VasquezGomezVI>);

}  // namespace nbs
