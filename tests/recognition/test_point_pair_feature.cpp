// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include "nbs/recognition/point_pair_feature.hpp"

using namespace nbs;

namespace {
constexpr double kPi = std::numbers::pi;
}

TEST_CASE("point_pair_feature of hand-built pairs matches Eq. 3.9", "[recognition]") {
  // d = (3, 4, 0), ‖d‖ = 5; n1 = +z ⟂ d; n2 = +x: ∠(n2, d) = acos(3/5); ∠(n1, n2) = π/2.
  const Eigen::Vector4d f = point_pair_feature(Vec3(1, 1, 1), Vec3::UnitZ(), Vec3(4, 5, 1), Vec3::UnitX());
  CHECK(f[0] == Approx(5.0));
  CHECK(f[1] == Approx(kPi / 2));
  CHECK(f[2] == Approx(std::acos(0.6)));
  CHECK(f[3] == Approx(kPi / 2));
  // Parallel and antiparallel normals along d: angles exactly 0 and π.
  const Eigen::Vector4d g = point_pair_feature(Vec3::Zero(), Vec3::UnitX(), Vec3(2, 0, 0), -Vec3::UnitX());
  CHECK(g[0] == 2.0);
  CHECK(g[1] == 0.0);
  CHECK(g[2] == Approx(kPi));
  CHECK(g[3] == Approx(kPi));
  // Swapping the points: ∠(n, −d) = π − ∠(n, d).
  const Vec3 p1(0.1, -0.2, 0.3), n1 = Vec3(1, 2, 3).normalized(), p2(-0.4, 0.5, 0.05), n2 = Vec3(-2, 1, 0.5).normalized();
  const Eigen::Vector4d a = point_pair_feature(p1, n1, p2, n2), b = point_pair_feature(p2, n2, p1, n1);
  CHECK(a[0] == Approx(b[0]));
  CHECK(a[1] == Approx(kPi - b[2]));
  CHECK(a[2] == Approx(kPi - b[1]));
  CHECK(a[3] == Approx(b[3]));
  CHECK(a[1] == Approx(std::acos(n1.dot((p2 - p1).normalized()))));
}

TEST_CASE("PpfQuantizer: bin edges, π, the distance cap and the key layout", "[recognition]") {
  const PpfQuantizer q{0.01, 2.0 * kPi / 30};
  CHECK(q.angle_bins() == 15);
  CHECK(q.angle_bin(0.0) == 0);
  CHECK(q.angle_bin(std::nextafter(q.angle_step_rad, 0.0)) == 0);
  CHECK(q.angle_bin(q.angle_step_rad * 1.000001) == 1);
  CHECK(q.angle_bin(kPi) == 14);  // π shares the last bin
  CHECK(q.angle_bin(std::nextafter(kPi, 0.0)) == 14);
  CHECK(q.angle_bin(-1e-12) == 0);  // clamped
  CHECK(q.distance_bin(0.0) == 0);
  CHECK(q.distance_bin(0.0099999) == 0);
  CHECK(q.distance_bin(0.0100001) == 1);
  CHECK(q.distance_bin(1e9) == PpfQuantizer::kMaxDistanceBin);
  CHECK(q.key({0.025, 0.0, kPi, kPi / 2 + 1e-9}) == ((std::uint64_t{2} << 48) | (std::uint64_t{0} << 32) |
                                                     (std::uint64_t{14} << 16) | std::uint64_t{7}));
  CHECK(PpfQuantizer{1.0, kPi}.angle_bins() == 1);
  CHECK(PpfQuantizer{1.0, 1.0}.angle_bins() == 4);  // ⌈π⌉
  CHECK_THROWS_WITH(PpfQuantizer({0.0, 0.1}).validate(), nbs_test::Contains("distance_step_m"));
  CHECK_THROWS_WITH(PpfQuantizer({0.01, 4.0}).validate(), nbs_test::Contains("angle_step_rad"));
  CHECK_THROWS_WITH(PpfQuantizer({0.01, 1e-4}).validate(), nbs_test::Contains("angle_step_rad must be in [pi/4096, pi], got 0.0001"));
  CHECK_NOTHROW(PpfQuantizer({0.01, kPi / 4096}).validate());
  CHECK_THROWS_WITH(PpfQuantizer({std::numeric_limits<double>::quiet_NaN(), 0.1}).validate(),
                    nbs_test::Contains("nan"));
}

TEST_CASE("align_normal_to_x and pair_angle: R_x(α_s − α_m) maps a model pair onto the scene pair", "[recognition]") {
  for (const Vec3& n : {Vec3(0.3, -0.5, 0.8).normalized(), Vec3(-1, 0, 0), Vec3(1, 0, 0), Vec3(0, 0, -1)}) {
    const Mat3 r = align_normal_to_x(n);
    CHECK((r * n - Vec3::UnitX()).norm() < 1e-12);
    CHECK(r.determinant() == Approx(1.0));
  }
  // A rigid motion T maps (m_r, n_r, m_i) to (s_r, n_s, s_i); then T = T_sg⁻¹ R_x(α_s − α_m) T_mg.
  const Pose t = Eigen::Translation3d(0.1, 0.2, -0.3) * Eigen::AngleAxisd(1.1, Vec3(1, -2, 0.5).normalized());
  const Vec3 mr(0.01, 0.02, 0.03), nm = Vec3(0.2, 0.9, -0.1).normalized(), mi(0.05, -0.04, 0.07);
  const Vec3 sr = t * mr, ns = t.linear() * nm, si = t * mi;
  const Mat3 rm = align_normal_to_x(nm), rs = align_normal_to_x(ns);
  const double alpha = pair_angle(rs, sr, si) - pair_angle(rm, mr, mi);
  Pose tmg = Pose::Identity(), tsg = Pose::Identity();
  tmg.linear() = rm, tmg.translation() = -(rm * mr);
  tsg.linear() = rs, tsg.translation() = -(rs * sr);
  const Pose back = tsg.inverse() * Pose(Eigen::AngleAxisd(alpha, Vec3::UnitX())) * tmg;
  CHECK((back.matrix() - t.matrix()).norm() < 1e-12);
}
