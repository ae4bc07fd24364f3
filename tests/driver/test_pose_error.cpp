// SPDX-License-Identifier: BSD-3-Clause
// Simulated pose error (sim/pose_error.hpp, driver/pose_error_driver.hpp): the error model's magnitudes are exact,
// deterministic in (seed, i), different per path, zero is the identity; the residual against hand-computed
// transforms; PoseErrorDriver reports E·(true scan), is bit-identical with zero error, passes the ScanDriver
// conformance suite.

#include "nbs_catch.hpp"

#include <cmath>
#include <numbers>

#include "nbs/driver/pose_error_driver.hpp"
#include "nbs/driver/simulated_driver.hpp"
#include "nbs/sim/initial_scan_paths.hpp"
#include "nbs/sim/pose_error.hpp"
#include "scan_driver_conformance.hpp"
#include "support/analytic_scanner.hpp"

namespace {

using nbs::Pose;
using nbs::Vec3;

constexpr double kDeg = std::numbers::pi / 180.0;

double angle_of(const Pose& p) { return Eigen::AngleAxisd(p.linear()).angle(); }

nbs::LinearScanPath sphere_path(int i) { return nbs::initial_scan_path(nbs::test::sphere_box(), 0.3, i); }

}  // namespace

TEST_CASE("pose error model: exact magnitudes, deterministic, different per path, zero is identity",
          "[sim][pose_error]") {
  nbs::PoseErrorSetting s;
  s.seed = 5;
  CHECK(s.translation_m == 0.001);
  CHECK(s.rotation_rad == Approx(0.1 * kDeg));
  const nbs::PoseErrorModel model(s);
  const Vec3 s0(0.1, -0.2, 0.3);
  for (std::uint64_t i = 0; i < 8; ++i) {
    const Pose E = model.error(i, s0);
    CHECK(E.linear().isUnitary(1e-12));
    CHECK(E.linear().determinant() == Approx(1.0));
    CHECK(angle_of(E) == Approx(s.rotation_rad).epsilon(1e-9));
    CHECK((E * s0 - s0).norm() == Approx(s.translation_m).epsilon(1e-12));  // the axis passes through s0
    CHECK(model.error(i, s0).matrix() == E.matrix());                        // deterministic
    CHECK(nbs::PoseErrorModel(s).error(i, s0).matrix() == E.matrix());
    CHECK((model.error(i + 1, s0).matrix() - E.matrix()).norm() > 1e-5);     // differs per path
  }
  nbs::PoseErrorSetting other = s;
  other.seed = 6;
  CHECK((nbs::PoseErrorModel(other).error(0, s0).matrix() - model.error(0, s0).matrix()).norm() > 1e-5);
  nbs::PoseErrorSetting zero = s;
  zero.translation_m = 0.0;
  zero.rotation_rad = 0.0;
  CHECK(zero.zero());
  CHECK(nbs::PoseErrorModel(zero).error(3, s0).matrix() == Pose::Identity().matrix());
  nbs::PoseErrorSetting bad = s;
  bad.translation_m = -1e-3;
  CHECK_THROWS_AS(bad.validate(), nbs::InvalidArgument);
  bad = s;
  bad.rotation_rad = std::numeric_limits<double>::infinity();
  CHECK_THROWS_AS(nbs::PoseErrorModel(bad), nbs::InvalidArgument);
}

TEST_CASE("residual pose error against hand-computed transforms", "[sim][pose_error]") {
  // E: 90° about z through the origin, then +1 mm in x. At c = (0.1, 0, 0): E·c = (0.001, 0.1, 0), |E·c − c| = √(0.099² + 0.1²).
  Pose E = Pose::Identity();
  E.linear() = Eigen::AngleAxisd(std::numbers::pi / 2, Vec3::UnitZ()).toRotationMatrix();
  E.translation() = Vec3(0.001, 0, 0);
  const Vec3 c(0.1, 0.0, 0.0);
  nbs::PoseResidual r = nbs::residual_pose_error(E, Pose::Identity(), c);
  CHECK(r.translation_m == Approx(std::sqrt(0.099 * 0.099 + 0.1 * 0.1)));
  CHECK(r.rotation_rad == Approx(std::numbers::pi / 2));
  // The exact inverse as correction leaves nothing.
  r = nbs::residual_pose_error(E, E.inverse(), c);
  CHECK(r.translation_m == Approx(0.0).margin(1e-15));
  CHECK(r.rotation_rad == Approx(0.0).margin(1e-7));
  // A pure translation of 2 mm corrected by −1.5 mm in the same direction: 0.5 mm left, no rotation, anywhere.
  Pose T = Pose::Identity(), C = Pose::Identity();
  T.translation() = Vec3(0, 0.002, 0);
  C.translation() = Vec3(0, -0.0015, 0);
  r = nbs::residual_pose_error(T, C, Vec3(5, 6, 7));
  CHECK(r.translation_m == Approx(0.0005));
  CHECK(r.rotation_rad == 0.0);
  // A rotation of 0.1° about an axis through c moves c not at all.
  Pose Rc = Pose::Identity();
  Rc.linear() = Eigen::AngleAxisd(0.1 * kDeg, Vec3::UnitX()).toRotationMatrix();
  Rc.translation() = c - Rc.linear() * c;
  r = nbs::residual_pose_error(Rc, Pose::Identity(), c);
  CHECK(r.translation_m == Approx(0.0).margin(1e-15));
  CHECK(r.rotation_rad == Approx(0.1 * kDeg));
}

TEST_CASE("PoseErrorDriver: reported scan = E·(true scan); zero error is bit-identical", "[driver][pose_error]") {
  const nbs::test::SphereOnPedestal sphere;
  const auto lsp = nbs::test::light_lsp();
  nbs::PoseErrorSetting s;
  s.seed = 9;
  s.translation_m = 0.002;
  s.rotation_rad = 0.3 * kDeg;
  nbs::SimulatedDriver truth(sphere, lsp, 3);
  nbs::PoseErrorDriver err(nbs::SimulatedDriver(sphere, lsp, 3), s);
  for (int i : {0, 5}) {
    const nbs::LinearScanPath path = sphere_path(i);
    const nbs::Scan t = truth.acquire(path);
    const nbs::Scan r = err.acquire(path);
    REQUIRE(!t.empty());
    REQUIRE(r.size() == t.size());
    REQUIRE_NOTHROW(r.validate());
    const nbs::PoseErrorRecord& e = err.last_error();
    CHECK(e.error.matrix() == err.model().error(e.path_index, path.start().pose().translation()).matrix());
    CHECK(e.true_to_reported.matrix().isApprox(e.error.matrix(), 1e-12));
    Vec3 c = Vec3::Zero();
    double worst = 0.0;
    for (std::size_t j = 0; j < t.size(); ++j) {
      c += t.points[j];
      worst = std::max(worst, (r.points[j] - e.error * t.points[j]).norm());
    }
    CHECK(worst < 1e-12);
    CHECK((e.true_centroid - c / static_cast<double>(t.size())).norm() < 1e-12);
    for (std::size_t k = 0; k < t.profile_poses.size(); ++k)
      CHECK((r.profile_poses[k].matrix() - (e.error * t.profile_poses[k]).matrix()).cwiseAbs().maxCoeff() < 1e-12);
    CHECK(err.current_pose().matrix() == path.pose_at(1.0).matrix());  // the commanded pose
  }
  // Zero error: the same scans, bit for bit.
  nbs::PoseErrorSetting zero;
  zero.translation_m = 0.0;
  zero.rotation_rad = 0.0;
  nbs::SimulatedDriver plain(sphere, lsp, 4);
  nbs::PoseErrorDriver none(nbs::SimulatedDriver(sphere, lsp, 4), zero);
  for (int i : {1, 7}) CHECK(nbs::conformance::detail::same_scan(none.acquire(sphere_path(i)), plain.acquire(sphere_path(i))));
  CHECK(none.last_error().error.matrix() == Pose::Identity().matrix());
}

TEST_CASE("PoseErrorDriver: a hand-eye error Δ gives T' = E·T·Δ and p' = T'·T⁻¹·p", "[driver][pose_error]") {
  const nbs::test::SphereOnPedestal sphere;
  const auto lsp = nbs::test::light_lsp();
  nbs::PoseErrorSetting s;
  s.hand_eye_error.linear() = Eigen::AngleAxisd(0.2 * kDeg, Vec3::UnitY()).toRotationMatrix();
  s.hand_eye_error.translation() = Vec3(0.0005, 0.0, 0.0);
  nbs::SimulatedDriver truth(sphere, lsp, 3);
  nbs::PoseErrorDriver err(nbs::SimulatedDriver(sphere, lsp, 3), s);
  const nbs::LinearScanPath path = sphere_path(2);
  const nbs::Scan t = truth.acquire(path);
  const nbs::Scan r = err.acquire(path);
  REQUIRE(!t.empty());
  const Pose E = err.last_error().error;
  double worst = 0.0;
  for (std::size_t j = 0; j < t.size(); ++j) {
    const Pose T = t.profile_poses[t.profile_of_point[j]];
    const Pose Tr = E * T * s.hand_eye_error;
    worst = std::max(worst, (r.points[j] - Tr * (T.inverse() * t.points[j])).norm());
    worst = std::max(worst, (r.profile_poses[t.profile_of_point[j]].matrix() - Tr.matrix()).cwiseAbs().maxCoeff());
  }
  CHECK(worst < 1e-12);
}

TEST_CASE("ScanDriver conformance: PoseErrorDriver over SimulatedDriver", "[driver][conformance][pose_error]") {
  // move_to / current_pose forward to the wrapped driver (a robot reports the commanded pose; its absolute error is
  // invisible to it), so the default tolerance holds; the determinism check holds since E_i depends on (seed, i).
  const nbs::test::SphereOnPedestal sphere;
  nbs::conformance::DriverCase c;
  for (int i : {0, 5}) c.paths.push_back(sphere_path(i));
  nbs::PoseErrorSetting s;
  s.seed = 11;
  nbs::conformance::check_scan_driver_conformance(
      [&] { return nbs::PoseErrorDriver(nbs::SimulatedDriver(sphere, nbs::test::light_lsp(), 3), s); }, c);
}
