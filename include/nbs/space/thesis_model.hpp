// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The thesis's update model (Sec. 3.3.2, after Suppa 2008 and Konolige's MURIEL): an inverse sensor model with
/// distance-dependent noise σ(d), evidence precomputed into a lookup table (Fig. 3.10), Bayes update of the free
/// and surf states (Eqs. 3.4–3.5), the specular state (Eq. 3.6) and occupancy via Eqs. 3.7–3.8.
///
/// Our reading of the equations (the thesis gives the curves only as a figure):
/// - Inverse model for a beam with measured range r, voxel centre at distance d along the beam, z = (d − r)/σ(r):
///   P(occ | z) = p_free + (p_hit − p_free)·exp(−z²/2) for z ≤ 0 (in front of the surface) and
///   0.5 + (p_hit − 0.5)·exp(−z²/2) for z > 0 (behind it: back to unknown); |z| > band_sigmas: no update.
///   Voxels in front of the band get P(occ) = p_free. The voxel containing the end point always gets z = 0.
/// - Bayes update (Eq. 3.4) of independent measurements in log form: the evidence e = log(P/(1−P)) is added to
///   log L_surf if e > 0 and to log L_free if e < 0 (L_free, L_surf: likelihood quotients of Eq. 3.7).
/// - Eq. 3.6 P(spec) = min(log(P(surf))/3, 1) is read with log(P(surf)) = log L_surf (a log of a probability
///   would be ≤ 0 and the equation vacuous); it is set whenever the voxel is measured free.
/// - Eq. 3.8: l = log L_surf + log(L_free·(1 − P(spec)) + P(spec)); p = 1 − 1/(1 + exp(l)). Unknown: p = 0.5.
///   A voxel with strong surface evidence (P(spec) → 1) is therefore not erased by later free measurements,
///   the behaviour the thesis wants for beams deflected by specular surfaces.
/// States are fixed point (1/1024 nat, saturating int16): 8 bytes as a value (7 used). Inside a HashedBlockBackend
/// block a voxel takes 4 bytes (free, direction) plus 3 bytes (surf, spec) only in blocks with surface evidence,
/// see BlockStates<ThesisState> below.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <memory>
#include <optional>
#include <utility>

#include "nbs/core/error.hpp"
#include "nbs/space/block_states.hpp"
#include "nbs/space/update_model.hpp"

namespace nbs {

/// Per-voxel state of the thesis model (8 bytes as a value, one byte of padding).
struct ThesisState {
  static constexpr std::uint16_t kNoDirection = 0xFFFF;
  std::int16_t free = 0;                      ///< log L_free in 1/1024 nat (≤ 0), Eq. 3.7
  std::int16_t surf = 0;                      ///< log L_surf in 1/1024 nat (≥ 0), Eq. 3.7
  std::uint8_t spec = 0;                      ///< P(spec)·255, Eq. 3.6
  std::uint16_t direction = kNoDirection;     ///< octahedral code of the last integrated beam (beam independence)
  [[nodiscard]] friend bool operator==(const ThesisState&, const ThesisState&) = default;
};

/// Block layout of ThesisState in HashedBlockBackend: `free` and `direction` (stored XOR kNoDirection, so a zeroed
/// block reads as unknown) for every voxel, 4 bytes each; `surf` and `spec` in a side-car of 3 bytes per voxel that
/// is allocated the first time a voxel of the block gets surface evidence (most observed blocks are free space).
template <>
struct BlockStates<ThesisState> {
  struct Surface {
    std::array<std::int16_t, kBlockVoxels> surf{};
    std::array<std::uint8_t, kBlockVoxels> spec{};
  };
  std::array<std::int16_t, kBlockVoxels> free{};
  std::array<std::uint16_t, kBlockVoxels> direction_x{};  ///< direction XOR kNoDirection
  std::unique_ptr<Surface> surface;                        ///< null: surf = spec = 0 for every voxel

  [[nodiscard]] ThesisState load(int i) const {
    ThesisState s;
    s.free = free[i];
    s.direction = static_cast<std::uint16_t>(direction_x[i] ^ ThesisState::kNoDirection);
    if (surface) {
      s.surf = surface->surf[i];
      s.spec = surface->spec[i];
    }
    return s;
  }
  void store(int i, const ThesisState& s) {
    free[i] = s.free;
    direction_x[i] = static_cast<std::uint16_t>(s.direction ^ ThesisState::kNoDirection);
    if (!surface) {
      if (s.surf == 0 && s.spec == 0) return;
      surface = std::make_unique<Surface>();
    }
    surface->surf[i] = s.surf;
    surface->spec[i] = s.spec;
  }
  [[nodiscard]] std::size_t heap_bytes() const { return surface ? sizeof(Surface) : 0; }
  template <class Write>
  void save(Write&& write) const {
    write(free.data(), sizeof(free));
    write(direction_x.data(), sizeof(direction_x));
    const std::uint8_t has_surface = surface ? 1 : 0;
    write(&has_surface, 1);
    if (surface) {
      write(surface->surf.data(), sizeof(surface->surf));
      write(surface->spec.data(), sizeof(surface->spec));
    }
  }
  template <class Read>
  [[nodiscard]] bool restore(Read&& read) {
    std::uint8_t has_surface = 0;
    if (!read(free.data(), sizeof(free)) || !read(direction_x.data(), sizeof(direction_x)) || !read(&has_surface, 1))
      return false;
    if (has_surface > 1) return false;
    surface.reset();
    if (has_surface == 0) return true;
    surface = std::make_unique<Surface>();
    return read(surface->surf.data(), sizeof(surface->surf)) && read(surface->spec.data(), sizeof(surface->spec));
  }
};

/// Thesis update model. Thread-safety: const members are safe to call concurrently if `sigma_m` is.
class ThesisModel {
public:
  using State = ThesisState;
  static constexpr double kScale = 1024.0;    ///< fixed-point units per nat
  static constexpr int kLutSize = 1025;       ///< lookup-table entries over z ∈ [−band_sigmas, band_sigmas]

  struct Setting {
    /// σ(d): standard deviation of the range noise (metres) at range d (metres); must return a finite value > 0.
    std::function<double(double)> sigma_m = [](double) { return 0.0005; };
    double prob_hit = 0.7;           ///< peak P(occ) at the measured range
    double prob_free = 0.4;          ///< P(occ) in front of the measured range
    double band_sigmas = 3.0;        ///< half width of the updated band around the end point, in σ
    double spec_divisor = 3.0;       ///< the constant 3 of Eq. 3.6
    double occupancy_threshold = 0.5;  ///< p ≥ this: occupied (Sec. 4.5.1 uses 0.95 for surface features)
    /// Beam independence: a beam whose direction lies within this many octahedral cells (8 bit per coordinate,
    /// ≈ 0.7° each) of the last beam integrated in a voxel is rejected there. −1 disables the test.
    int similar_direction_cells = 2;
    void validate() const {
      detail::require(static_cast<bool>(sigma_m), "ThesisModel: sigma_m is empty");
      detail::require(prob_free > 0.0 && prob_free < 0.5 && prob_hit > 0.5 && prob_hit < 1.0,
                      "ThesisModel: need 0 < prob_free < 0.5 < prob_hit < 1, got ", prob_free, ", ", prob_hit);
      detail::require_in_range("band_sigmas", band_sigmas, 0.5, 10.0);
      detail::require_positive("spec_divisor", spec_divisor);
      detail::require(occupancy_threshold > 0.0 && occupancy_threshold < 1.0,
                      "ThesisModel: occupancy_threshold must be in (0, 1), got ", occupancy_threshold);
      detail::require(similar_direction_cells >= -1 && similar_direction_cells <= 254,
                      "ThesisModel: similar_direction_cells must be in [-1, 254], got ", similar_direction_cells);
    }
  };

  /// Per-beam data: 1/σ(r), band half width band_sigmas·σ(r), direction code.
  struct Beam {
    double inv_sigma = 0.0;
    double half_width_m = 0.0;
    std::uint16_t direction = ThesisState::kNoDirection;
  };

  ThesisModel() : ThesisModel(Setting{}) {}
  explicit ThesisModel(Setting s) : setting_(std::move(s)) {
    setting_.validate();
    free_ = to_fixed(logit(setting_.prob_free));
    const double zmax = setting_.band_sigmas;
    lut_scale_ = (kLutSize - 1) / (2.0 * zmax);
    for (int i = 0; i < kLutSize; ++i) lut_[i] = to_fixed(logit(inverse_model(i / lut_scale_ - zmax)));
    occupied_scaled_ = logit(setting_.occupancy_threshold) * kScale;
    spec_per_unit_ = 255.0 / (setting_.spec_divisor * kScale);
  }

  [[nodiscard]] const Setting& setting() const { return setting_; }

  /// Inverse sensor model P(occ | z), z = (d − r)/σ(r) (see file comment); 0.5 outside the band.
  [[nodiscard]] double inverse_model(double z) const {
    if (!(std::abs(z) <= setting_.band_sigmas)) return 0.5;
    const double g = std::exp(-0.5 * z * z);
    return z <= 0.0 ? setting_.prob_free + (setting_.prob_hit - setting_.prob_free) * g
                    : 0.5 + (setting_.prob_hit - 0.5) * g;
  }

  /// nullopt (beam rejected) if σ(range_m) is not finite and > 0.
  [[nodiscard]] std::optional<Beam> beam(double range_m, const Vec3& unit_direction) const {
    const double sigma = setting_.sigma_m(range_m);
    if (!(std::isfinite(sigma) && sigma > 0.0)) return std::nullopt;
    return Beam{1.0 / sigma, setting_.band_sigmas * sigma, encode_direction(unit_direction)};
  }
  [[nodiscard]] double band_half_width_m(const Beam& b) const { return b.half_width_m; }

  VoxelUpdate update_band(State& s, const Beam& b, double offset_m, bool end_voxel) const {
    const double z = end_voxel ? 0.0 : offset_m * b.inv_sigma;
    const double x = (z + setting_.band_sigmas) * lut_scale_;
    if (!(x >= 0.0 && x <= kLutSize - 1)) return VoxelUpdate::unchanged;
    if (similar(s.direction, b.direction)) return VoxelUpdate::similar_beam;
    apply(s, lut_[static_cast<int>(x + 0.5)]);
    s.direction = b.direction;
    return VoxelUpdate::updated;
  }
  VoxelUpdate update_free(State& s, const Beam& b) const {
    if (similar(s.direction, b.direction)) return VoxelUpdate::similar_beam;
    apply(s, free_);
    s.direction = b.direction;
    return VoxelUpdate::updated;
  }

  /// P(spec) ∈ [0, 1], Eq. 3.6.
  [[nodiscard]] static double spec_probability(const State& s) { return s.spec / 255.0; }
  /// l of Eq. 3.8 (natural log-odds of occupancy).
  [[nodiscard]] double log_odds(const State& s) const {
    const double ls = s.surf / kScale;
    const double lf = s.free / kScale;
    if (s.spec == 0) return ls + lf;
    const double spec = spec_probability(s);
    return ls + std::log(std::exp(lf) * (1.0 - spec) + spec);
  }
  [[nodiscard]] double probability(const State& s) const { return 1.0 - 1.0 / (1.0 + std::exp(log_odds(s))); }
  /// p ≥ occupancy_threshold and some surface evidence (the unknown state is never occupied).
  [[nodiscard]] bool occupied(const State& s) const {
    if (s.surf == 0) return false;
    if (s.spec == 0) return s.surf + s.free >= occupied_scaled_;
    return log_odds(s) * kScale >= occupied_scaled_;
  }

  /// Evidence table entry i (fixed point), i ∈ [0, kLutSize); z_i = i/(kLutSize−1)·2·band_sigmas − band_sigmas.
  [[nodiscard]] std::int16_t lut(int i) const { return lut_[i]; }
  /// Evidence of a free measurement (fixed point).
  [[nodiscard]] std::int16_t free_evidence() const { return free_; }

  /// Octahedral 8+8-bit code of a unit vector (u + 256·v, u, v ∈ [0, 254]).
  [[nodiscard]] static std::uint16_t encode_direction(const Vec3& d) {
    const double n = std::abs(d.x()) + std::abs(d.y()) + std::abs(d.z());
    if (!(n > 0.0) || !std::isfinite(n)) return ThesisState::kNoDirection;
    double px = d.x() / n, py = d.y() / n;
    if (d.z() < 0.0) {
      const double qx = (1.0 - std::abs(py)) * (px >= 0.0 ? 1.0 : -1.0);
      const double qy = (1.0 - std::abs(px)) * (py >= 0.0 ? 1.0 : -1.0);
      px = qx;
      py = qy;
    }
    const auto q = [](double v) {  // round to nearest of 0..254 (argument ≥ 0, so truncation of x + 0.5 rounds)
      return static_cast<std::uint16_t>(std::clamp(v, -1.0, 1.0) * 127.0 + 127.5);
    };
    return static_cast<std::uint16_t>(q(px) | (q(py) << 8));
  }

private:
  [[nodiscard]] static double logit(double p) { return std::log(p / (1.0 - p)); }
  [[nodiscard]] static std::int16_t to_fixed(double l) {
    return static_cast<std::int16_t>(std::clamp(std::lround(l * kScale), -32767L, 32767L));
  }
  [[nodiscard]] bool similar(std::uint16_t a, std::uint16_t b) const {
    if (a == ThesisState::kNoDirection || setting_.similar_direction_cells < 0) return false;
    const int k = setting_.similar_direction_cells;
    return std::abs((a & 0xFF) - (b & 0xFF)) <= k && std::abs((a >> 8) - (b >> 8)) <= k;
  }
  void apply(State& s, int e) const {
    if (e >= 0) {
      s.surf = static_cast<std::int16_t>(std::min(32767, s.surf + e));
    } else {
      s.free = static_cast<std::int16_t>(std::max(-32767, s.free + e));
      // Eq. 3.6, updated only when the voxel is measured free (surf ≥ 0, so spec stays 0 without surface evidence).
      if (s.surf > 0) s.spec = static_cast<std::uint8_t>(std::min(255.0, std::round(s.surf * spec_per_unit_)));
    }
  }

  Setting setting_;
  std::array<std::int16_t, kLutSize> lut_{};
  std::int16_t free_ = 0;
  double lut_scale_ = 1.0;
  double occupied_scaled_ = 0.0;
  double spec_per_unit_ = 0.0;
};

}  // namespace nbs
