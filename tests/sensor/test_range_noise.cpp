// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include <cmath>

#include "nbs/sensor/counter_gaussian.hpp"
#include "nbs/sensor/presets.hpp"
#include "nbs/sensor/range_noise.hpp"

using nbs_test::Contains;

TEST_CASE("Eq. 4.39 in SI units matches the millimetre polynomial evaluated by hand", "[sensor][noise]") {
  const auto n = nbs::RangeNoise::thesis_lsp();
  // σ(d̃) = 0.005 + 0.0005 d̃ + 1.026e-5 d̃² + 1.9979e-9 d̃³ + 1.2655e-12 d̃⁴, evaluated by hand (mm):
  // d̃ = 150: 0.005 + 0.075 + 0.23085 + 0.006742913 + 0.000640659 = 0.318233572
  // d̃ = 300: 0.005 + 0.15 + 0.9234 + 0.05394330 + 0.01025055 = 1.14259385
  // d̃ = 450: 0.005 + 0.225 + 2.07765 + 0.182058638 + 0.051893409 = 2.541602047
  CHECK(n.sigma_m(0.150) == Approx(0.318233572e-3).epsilon(1e-8));
  CHECK(n.sigma_m(0.300) == Approx(1.14259385e-3).epsilon(1e-8));
  CHECK(n.sigma_m(0.450) == Approx(2.541602047e-3).epsilon(1e-8));
  CHECK(n.sigma_m(0.0) == Approx(0.005e-3));
}

TEST_CASE("constant and quadratic noise models", "[sensor][noise]") {
  CHECK(nbs::RangeNoise().is_zero());
  CHECK(nbs::RangeNoise().sigma_m(1.0) == 0.0);
  const auto c = nbs::RangeNoise::constant(2e-4);
  CHECK(c.sigma_m(0.1) == Approx(2e-4));
  CHECK(c.sigma_m(3.0) == Approx(2e-4));
  const auto q = nbs::RangeNoise::quadratic(1.425e-3);
  CHECK(q.sigma_m(2.0) == Approx(1.425e-3 * 4.0));
  CHECK_FALSE(q.is_zero());
  // Guppy stereo: σ = d² · 0.25 px / (f · 0.08 m), f = 646 px / tan(28.7°) ≈ 1180 px → 2.648e-3 · d².
  CHECK(nbs::presets::guppy_pro_stereo().noise.sigma_m(1.0) == Approx(2.6484e-3).epsilon(1e-3));
  CHECK_THROWS_AS(nbs::RangeNoise::constant(-1.0), nbs::InvalidArgument);
  CHECK_THROWS_WITH(nbs::RangeNoise::quadratic(std::nan("")), Contains("k_per_m"));
  CHECK_THROWS_WITH(nbs::RangeNoise::polynomial_si({0, 0, INFINITY, 0, 0}), Contains("a_2"));
}

TEST_CASE("CounterGaussian: standard normal statistics, seeded and order independent", "[sensor][noise]") {
  const nbs::CounterGaussian g(42);
  const int n = 200000;
  double sum = 0.0, sum2 = 0.0;
  for (int i = 0; i < n; ++i) {
    const double z = g(static_cast<std::uint64_t>(i % 500), static_cast<std::uint64_t>(i / 500));
    sum += z;
    sum2 += z * z;
  }
  const double mean = sum / n;
  const double var = sum2 / n - mean * mean;
  // 5-sigma bounds: mean ~ N(0, 1/n), sample variance ~ N(1, 2/n) (chi-square with n dof, scaled).
  CHECK(std::abs(mean) < 5.0 / std::sqrt(n));
  CHECK(std::abs(var - 1.0) < 5.0 * std::sqrt(2.0 / n));
  CHECK(g(3, 7) == nbs::CounterGaussian(42)(3, 7));
  CHECK(g(3, 7) != nbs::CounterGaussian(43)(3, 7));
  CHECK(g(3, 7) != g(7, 3));
}
