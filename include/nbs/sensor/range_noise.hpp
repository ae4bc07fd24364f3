// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Distance-dependent range noise σ(d) of a sensor: a polynomial in the true distance d along the ray.

#include <array>
#include <string>

#include "nbs/core/error.hpp"

namespace nbs {

/// Standard deviation σ(d) of a range measurement along the ray, as a polynomial of degree ≤ 4 in the true
/// distance d: σ(d) = Σ a_i dⁱ, SI units (σ and d in metres). Build it with the named factories; every model the
/// presets use (thesis polynomial, constant, quadratic) is such a polynomial. Immutable, thread-safe.
class RangeNoise {
public:
  static constexpr int kMaxDegree = 4;
  using Coefficients = std::array<double, kMaxDegree + 1>;

  /// No noise: σ ≡ 0.
  RangeNoise() = default;

  /// σ_m(d_m) = Σ a_i d_mⁱ with `a` in SI units (a_i in m^(1−i)). Throws InvalidArgument on non-finite a_i.
  [[nodiscard]] static RangeNoise polynomial_si(const Coefficients& a) {
    for (std::size_t i = 0; i < a.size(); ++i)
      detail::require(std::isfinite(a[i]), "noise coefficient a_", i, " must be finite, got ", a[i]);
    RangeNoise n;
    n.a_ = a;
    return n;
  }

  /// Polynomial given in millimetres, as Eq. (4.39) is: σ_mm(d̃) = Σ c_i d̃ⁱ with d̃ in mm. Converted to SI as
  /// σ_m(d_m) = 1e-3 · σ_mm(1e3 · d_m), i.e. a_i = c_i · 1e-3 · 1e3ⁱ.
  [[nodiscard]] static RangeNoise polynomial_mm(const Coefficients& c_mm) {
    Coefficients a{};
    double scale = 1e-3;
    for (std::size_t i = 0; i < a.size(); ++i, scale *= 1e3) a[i] = c_mm[i] * scale;
    return polynomial_si(a);
  }

  /// Eq. (4.39), the DLR laser stripe profiler model used in the thesis simulation (after Suppa et al. 2007):
  /// σ(d̃) = 0.005 + 0.0005 d̃ + 1.026e-5 d̃² + 1.9979e-9 d̃³ + 1.2655e-12 d̃⁴, σ and d̃ read as millimetres.
  /// Example: σ(300 mm) ≈ 1.14 mm.
  [[nodiscard]] static RangeNoise thesis_lsp() {
    return polynomial_mm({0.005, 0.0005, 1.026e-5, 1.9979e-9, 1.2655e-12});
  }

  /// σ ≡ sigma_m (metres, ≥ 0).
  [[nodiscard]] static RangeNoise constant(double sigma_m) {
    detail::require_non_negative("constant noise sigma_m", sigma_m);
    return polynomial_si({sigma_m, 0, 0, 0, 0});
  }

  /// σ = k · d² (σ, d in metres; k in 1/m, ≥ 0): the depth error of triangulating sensors (stereo, structured
  /// light), which grows with the square of the distance.
  [[nodiscard]] static RangeNoise quadratic(double k_per_m) {
    detail::require_non_negative("quadratic noise k_per_m", k_per_m);
    return polynomial_si({0, 0, k_per_m, 0, 0});
  }

  /// σ(d) in metres for a true distance d in metres (Horner). Clamped at 0 from below.
  [[nodiscard]] double sigma_m(double d_m) const {
    double s = 0.0;
    for (int i = kMaxDegree; i >= 0; --i) s = s * d_m + a_[static_cast<std::size_t>(i)];
    return s > 0.0 ? s : 0.0;
  }

  /// True if σ ≡ 0.
  [[nodiscard]] bool is_zero() const {
    for (double a : a_)
      if (a != 0.0) return false;
    return true;
  }

  /// SI coefficients a_0..a_4.
  [[nodiscard]] const Coefficients& coefficients_si() const { return a_; }

private:
  Coefficients a_{};
};

}  // namespace nbs
