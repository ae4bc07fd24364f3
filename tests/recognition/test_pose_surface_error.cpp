// SPDX-License-Identifier: BSD-3-Clause
// ADD / ADD-S (recognition/pose_surface_error.hpp) against analytic cases and a brute-force nearest neighbour.
#include "nbs_catch.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "nbs/recognition/pose_surface_error.hpp"
#include "nbs_random.hpp"

namespace {

using nbs::Pose;
using nbs::Vec3;

/// Side samples of a cylinder about z: radius r, `around` angles k·2π/around, `heights` rings in [0, h].
std::vector<Vec3> surface_error_cylinder(double r, double h, int around, int heights) {
  std::vector<Vec3> s;
  for (int j = 0; j < heights; ++j)
    for (int k = 0; k < around; ++k) {
      const double a = 2.0 * std::numbers::pi * k / around;
      s.emplace_back(r * std::cos(a), r * std::sin(a), h * j / (heights - 1));
    }
  return s;
}

Pose surface_error_pose(double angle_z, const Vec3& t) {
  Pose T = Pose::Identity();
  T.linear() = Eigen::AngleAxisd(angle_z, Vec3::UnitZ()).toRotationMatrix();
  T.translation() = t;
  return T;
}

}  // namespace

TEST_CASE("ADD-S is zero for a turn by a symmetry of the samples, ADD is the chord", "[recognition][pose_error]") {
  const double r = 0.04;
  const std::vector<Vec3> s = surface_error_cylinder(r, 0.1, 36, 5);
  const nbs::SurfacePoseMetric m(s);
  const Vec3 at(0.3, -0.2, 0.75);
  const Pose truth = surface_error_pose(0.4, at);
  const double turn = 2.0 * std::numbers::pi * 5 / 36;  // 50°: maps the samples onto themselves
  const nbs::SurfacePoseError e = m.error(truth * surface_error_pose(turn, Vec3::Zero()), truth);
  CHECK(e.add_s_m == Approx(0.0).margin(1e-12));
  CHECK(e.add_s_max_m == Approx(0.0).margin(1e-12));
  CHECK(e.add_m == Approx(2.0 * r * std::sin(turn / 2.0)).epsilon(1e-12));  // every sample moves by the chord
  const nbs::SurfacePoseError same = m.error(truth, truth);
  CHECK(same.add_m == Approx(0.0).margin(1e-15));
  CHECK(same.add_s_m == Approx(0.0).margin(1e-15));
}

TEST_CASE("ADD is the shift of a translation; ADD-S equals a brute-force nearest neighbour", "[recognition][pose_error]") {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  std::vector<Vec3> s(400);
  for (Vec3& p : s) p = nbs_test::random_vec3(u, rng).cwiseProduct(Vec3(1.0, 1.0, 0.5));
  const nbs::SurfacePoseMetric m(s);
  const Pose truth = surface_error_pose(-1.1, Vec3(0.1, 0.2, 0.0));
  const Vec3 shift(0.003, -0.004, 0.0);  // 5 mm in the model frame
  Pose est = truth * surface_error_pose(0.0, shift);
  CHECK(m.error(est, truth).add_m == Approx(0.005).epsilon(1e-12));
  est = truth * surface_error_pose(0.3, shift);
  const nbs::SurfacePoseError e = m.error(est, truth);
  double mean = 0.0, worst = 0.0;
  for (const Vec3& p : s) {
    const Vec3 q = truth.inverse() * est * p;
    double best = std::numeric_limits<double>::infinity();
    for (const Vec3& o : s) best = std::min(best, (q - o).norm());
    mean += best;
    worst = std::max(worst, best);
  }
  CHECK(e.add_s_m == Approx(mean / s.size()).epsilon(1e-12));
  CHECK(e.add_s_max_m == Approx(worst).epsilon(1e-12));
  CHECK(e.add_s_m <= e.add_m);
}

TEST_CASE("ADD-S is not zero for a turn that is no symmetry (an L of samples)", "[recognition][pose_error]") {
  std::vector<Vec3> s;
  for (int i = 0; i <= 20; ++i) s.emplace_back(0.005 * i, 0.0, 0.0), s.emplace_back(0.0, 0.003 * i, 0.0);
  const nbs::SurfacePoseMetric m(s);
  const nbs::SurfacePoseError e = m.error(surface_error_pose(std::numbers::pi, Vec3::Zero()), Pose::Identity());
  CHECK(e.add_s_max_m == Approx(0.1).epsilon(1e-12));  // the long arm's tip (0.1, 0) lands at (−0.1, 0)
  CHECK(e.add_s_m > 0.02);
}

TEST_CASE("SurfacePoseMetric bad input", "[recognition][pose_error][bad]") {
  CHECK_THROWS_WITH(nbs::SurfacePoseMetric(std::vector<Vec3>{}), nbs_test::Contains("no model samples"));
  const std::vector<Vec3> nan{Vec3::Zero(), Vec3(std::nan(""), 0.0, 0.0)};
  CHECK_THROWS_WITH(nbs::SurfacePoseMetric(nan), nbs_test::Contains("model sample 1 is not finite"));
  const nbs::SurfacePoseMetric m(std::vector<Vec3>{Vec3::Zero(), Vec3::UnitX()});
  Pose bad = Pose::Identity();
  bad.linear() *= 2.0;
  CHECK_THROWS_WITH((void)m.error(bad, Pose::Identity()), nbs_test::Contains("estimated pose"));
  CHECK_THROWS_WITH((void)m.error(Pose::Identity(), bad), nbs_test::Contains("true pose"));
}
