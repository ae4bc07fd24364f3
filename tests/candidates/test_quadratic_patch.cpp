// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include <random>
#include <vector>

#include "nbs/candidates/quadratic_patch.hpp"

using nbs::Vec3;

namespace {
nbs::QuadraticPatch known() {
  nbs::QuadraticPatch q;
  q.a << 3.0, -1.5, 2.0, 0.2, -0.4, 0.3;  // curvatures of a few 1/m, metres-scale offsets
  q.rank = 6;
  return q;
}
}  // namespace

TEST_CASE("quadratic patch fit recovers a known quadric exactly without noise (Eqs. 4.5-4.10)", "[candidates]") {
  const auto truth = known();
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.05, 0.09);  // off-centre region: exercises the de-centring
  std::vector<Vec3> pts;
  std::vector<double> w;
  for (int i = 0; i < 60; ++i) {
    const double x = u(rng), y = u(rng) - 0.1;
    pts.push_back(truth.point(x, y));
    w.push_back(0.2 + 0.8 * (i % 3));
  }
  const auto fit = nbs::fit_quadratic_patch(pts, w);
  REQUIRE(fit);
  CHECK(fit->rank == 6);
  for (int k = 0; k < 6; ++k) CHECK(fit->a[k] == Approx(truth.a[k]).margin(1e-8));
  // Eq. 4.13 normal matches the analytic derivative
  const Vec3 n = fit->normal(0.07, -0.03);
  const double h = 1e-6;
  CHECK(n.x() == Approx((truth.z(0.07 + h, -0.03) - truth.z(0.07 - h, -0.03)) / (2 * h)).margin(1e-6));
  CHECK(n.y() == Approx((truth.z(0.07, -0.03 + h) - truth.z(0.07, -0.03 - h)) / (2 * h)).margin(1e-6));
  CHECK(n.z() == -1.0);
}

TEST_CASE("quadratic patch fit stays within tolerance with noise; weights pull the fit", "[candidates]") {
  const auto truth = known();
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-0.02, 0.02);
  std::normal_distribution<double> noise(0.0, 0.0002);  // 0.2 mm
  std::vector<Vec3> pts;
  std::vector<double> w;
  for (int i = 0; i < 400; ++i) {
    const double x = u(rng), y = u(rng);
    pts.push_back(truth.point(x, y) + Vec3(0, 0, noise(rng)));
    w.push_back(1.0);
  }
  const auto fit = nbs::fit_quadratic_patch(pts, w);
  REQUIRE(fit);
  double max_err = 0.0;
  for (double x = -0.02; x <= 0.02; x += 0.005)
    for (double y = -0.02; y <= 0.02; y += 0.005) max_err = std::max(max_err, std::abs(fit->z(x, y) - truth.z(x, y)));
  CHECK(max_err < 0.0002);  // within the noise level over the sampled region

  // An outlier with zero weight does not change the fit; with full weight it does.
  pts.push_back(Vec3(0, 0, 1.0));
  w.push_back(0.0);
  const auto f0 = nbs::fit_quadratic_patch(pts, w);
  REQUIRE(f0);
  CHECK((f0->a - fit->a).norm() < 1e-9);
  w.back() = 1.0;
  const auto f1 = nbs::fit_quadratic_patch(pts, w);
  REQUIRE(f1);
  CHECK(std::abs(f1->z(0, 0) - fit->z(0, 0)) > 1e-3);
}

TEST_CASE("quadratic patch fit degrades to a plane or nothing on degenerate input", "[candidates]") {
  std::vector<Vec3> line;
  std::vector<double> w;
  for (int i = 0; i < 10; ++i) {
    line.emplace_back(0.01 * i, 0.0, 0.5 + 0.02 * i);
    w.push_back(1.0);
  }
  CHECK_FALSE(nbs::fit_quadratic_patch(line, w));  // collinear in x-y: not even a plane is determined

  std::vector<Vec3> plane{{0, 0, 1}, {0.01, 0, 1.01}, {0, 0.01, 0.98}, {0.01, 0.01, 0.99}, {0.005, 0.005, 0.995}};
  std::vector<double> pw(plane.size(), 1.0);
  const auto fit = nbs::fit_quadratic_patch(plane, pw);
  REQUIRE(fit);
  CHECK(fit->rank == 3);
  CHECK(fit->a[3] == Approx(1.0).margin(1e-9));
  CHECK(fit->a[4] == Approx(-2.0).margin(1e-9));
  CHECK(fit->a[5] == Approx(1.0).margin(1e-12));

  std::vector<Vec3> bad{{0, 0, std::nan("")}, {1, 0, 0}, {0, 1, 0}};
  std::vector<double> bw(3, 1.0);
  CHECK_THROWS_AS(nbs::fit_quadratic_patch(bad, bw), nbs::InvalidArgument);
  CHECK_THROWS_AS(nbs::fit_quadratic_patch(plane, bw), nbs::InvalidArgument);  // size mismatch
  CHECK(nbs::boundary_distance_weight(0.001, 0.002) == 1.0);
  CHECK(nbs::boundary_distance_weight(0.004, 0.002) == Approx(0.5));
}
