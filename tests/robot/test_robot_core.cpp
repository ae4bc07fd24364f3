// SPDX-License-Identifier: BSD-3-Clause
// The Robot concept's core models and check_scan_path, against the hand-written planar 3R arm (planar_robot.hpp).
#include "nbs_catch.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "conformance/robot_conformance.hpp"
#include "nbs/robot/free_flying.hpp"
#include "nbs/robot/reachability.hpp"
#include "planar_robot.hpp"
#include "nbs_pose.hpp"

using nbs_test::rigid_pose;

using namespace nbs;
using nbs::test::PlanarArm;

namespace {

Pose at(double x, double y, double z) { return rigid_pose(Mat3::Identity(), Vec3(x, y, z)); }

JointVector jv(double a, double b, double c) {
  JointVector q(3);
  q << a, b, c;
  return q;
}

// Sensor looking along +x (φ = π/2) at height z, moving along x from x0 to x1: stays in the arm's plane.
LinearScanPath planar_path(double x0, double x1, double z) {
  Pose T = Pose::Identity();
  T.linear() = PlanarArm::rot_y(std::numbers::pi / 2);
  T.translation() = Vec3(x0, 0, z);
  return LinearScanPath(Viewpoint(T), Vec3(x1, 0, z));
}

// The elbow-up (θ2 ≥ 0) solution of the planar arm for the sensor at (x, 0, z) looking along +x, by hand.
JointVector planar_oracle(double x, double z, const PlanarArm& a) {
  const double wx = x - a.l[2], wz = z;
  const double c = (wx * wx + wz * wz - a.l[0] * a.l[0] - a.l[1] * a.l[1]) / (2 * a.l[0] * a.l[1]);
  const double t2 = std::acos(c);
  const double t1 = std::atan2(wx, wz) - std::atan2(a.l[1] * std::sin(t2), a.l[0] + a.l[1] * std::cos(t2));
  return jv(t1, t2, std::numbers::pi / 2 - t1 - t2);
}

}  // namespace

TEST_CASE("FreeFlyingSensor passes the Robot conformance suite", "[robot]") {
  static_assert(Robot<FreeFlyingSensor>);
  conformance::RobotCase c;
  c.position_tol_m = 1e-12;
  c.angle_tol_rad = 1e-9;
  const auto rep = conformance::check_robot_conformance(FreeFlyingSensor{}, c);
  CHECK(rep.ik_solved == rep.ik_tried);
}

TEST_CASE("FreeFlyingSensor: every pose is reachable, every path is flown, no links", "[robot]") {
  const FreeFlyingSensor r;
  CHECK(r.hand_eye().matrix() == Pose::Identity().matrix());
  std::mt19937_64 rng(7);
  const auto u = [&] { return 2.0 * nbs::detail::uniform01(rng) - 1.0; };
  for (int i = 0; i < 100; ++i) {
    Eigen::Vector4d q4;
    for (int k = 0; k < 4; ++k) q4[k] = u();  // one draw per statement: drawn in order, whatever the compiler
    Vec3 t;
    for (int k = 0; k < 3; ++k) t[k] = u();
    const Pose T = rigid_pose(Eigen::Quaterniond(q4.normalized()).toRotationMatrix(), t);
    const auto q = r.ik(T, JointVector::Zero(6));
    REQUIRE(q);
    CHECK((*q).head<3>().isApprox(T.translation(), 0.0));
    CHECK(poses_agree(r.fk(*q), T, 1e-12, 1e-9));
    CHECK(r.collision_shapes(*q).empty());
  }
  // A rotation of exactly π: ω and −ω are the same rotation; the one nearer the seed is taken.
  Pose half = Pose::Identity();
  half.linear() = Eigen::AngleAxisd(std::numbers::pi, Vec3::UnitZ()).toRotationMatrix();
  JointVector seed = JointVector::Zero(6);
  seed[5] = -3.0;
  CHECK(r.ik(half, seed)->tail<3>().isApprox(Vec3(0, 0, -std::numbers::pi), 1e-12));
  seed[5] = 3.0;
  CHECK(r.ik(half, seed)->tail<3>().isApprox(Vec3(0, 0, std::numbers::pi), 1e-12));

  // Any path, even a long one far away, is flown, sample positions on the path.
  Pose start = Pose::Identity();
  start.linear() = Eigen::AngleAxisd(2.0, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  start.translation() = Vec3(5, -3, 2);
  const LinearScanPath path(Viewpoint(start), Vec3(5.3, -3.2, 2.4));
  const ScanPathReach reach = check_scan_path(r, path, JointVector::Zero(6));
  REQUIRE(reach.ok());
  CHECK(reach.samples == static_cast<std::size_t>(std::ceil(path.length() / 0.01)) + 1);
  REQUIRE(reach.joints.size() == reach.samples);
  for (std::size_t i = 0; i < reach.samples; ++i)
    CHECK(poses_agree(r.fk(reach.joints[i]), path.pose_at(double(i) / double(reach.samples - 1)), 1e-12, 1e-9));
}

TEST_CASE("planar arm: hand-computed forward kinematics and conformance", "[robot]") {
  const PlanarArm a;
  // q = 0: straight up, sensor at (0, 0, 0.8) looking up.
  CHECK(poses_agree(a.fk(jv(0, 0, 0)), at(0, 0, 0.8), 1e-15, 1e-15));
  // q = (π/2, 0, 0): straight along +x.
  Pose T = Pose::Identity();
  T.linear() = PlanarArm::rot_y(std::numbers::pi / 2);
  T.translation() = Vec3(0.8, 0, 0);
  CHECK(poses_agree(a.fk(jv(std::numbers::pi / 2, 0, 0)), T, 1e-15, 1e-15));
  // q = (0, π/2, −π/2): up 0.4, across 0.3, up 0.1 → (0.3, 0, 0.5) looking up.
  CHECK(poses_agree(a.fk(jv(0, std::numbers::pi / 2, -std::numbers::pi / 2)), at(0.3, 0, 0.5),
                    1e-15, 1e-15));
  const auto rep = conformance::check_robot_conformance(a);
  CHECK(rep.ik_solved == rep.ik_tried);
  // Out of the plane or beyond reach: no solution.
  CHECK_FALSE(a.ik(at(0, 0.1, 0.5), jv(0, 0, 0)));
  CHECK_FALSE(a.ik(at(0, 0, 0.81), jv(0, 0, 0)));
}

TEST_CASE("check_scan_path: a path beyond reach fails at the first sample out of reach", "[robot]") {
  const PlanarArm a;
  // From x = 0.3 to 1.0 at z = 0.2, looking along +x: the wrist (x − 0.1, 0.2) is in reach while
  // (x − 0.1)² + 0.2² ≤ 0.7², i.e. x ≤ 0.1 + √0.45 = 0.77082. Samples every 0.01 m: 71, x_i = 0.3 + 0.01 i, so the
  // first sample out of reach is i = 48 (x = 0.78).
  const LinearScanPath path = planar_path(0.3, 1.0, 0.2);
  ScanPathReachSetting s;
  s.max_joint_step = 1.0;  // the elbow straightens fast near full reach; here only reach is tested
  const ScanPathReach r = check_scan_path(a, path, planar_oracle(0.3, 0.2, a), s);
  CHECK(r.samples == 71);
  REQUIRE_FALSE(r.ok());
  CHECK(r.failure == PathFailure::unreachable);
  CHECK(r.step == 48);
  CHECK(r.value == Approx(48.0 / 70.0));
  REQUIRE(r.joints.size() == 48);
  for (std::size_t i = 0; i < r.joints.size(); ++i) {
    const double x = 0.3 + 0.7 * double(i) / 70.0;
    INFO("step " << i);
    CHECK((r.joints[i] - planar_oracle(x, 0.2, a)).cwiseAbs().maxCoeff() < 1e-9);
  }
}

TEST_CASE("check_scan_path: the joint-jump bound is enforced", "[robot]") {
  const PlanarArm a;
  const LinearScanPath path = planar_path(0.3, 0.7, 0.2);  // in reach throughout; 41 samples
  // The oracle's largest joint change between consecutive samples, and where it is.
  double worst = 0.0;
  std::size_t worst_step = 0;
  for (std::size_t i = 1; i <= 40; ++i) {
    const double d = (planar_oracle(0.3 + 0.01 * double(i), 0.2, a) -
                      planar_oracle(0.3 + 0.01 * double(i - 1), 0.2, a)).cwiseAbs().maxCoeff();
    if (d > worst) worst = d, worst_step = i;
  }
  REQUIRE(worst > 0.05);
  ScanPathReachSetting s;
  s.max_joint_step = worst * 1.001;
  const ScanPathReach ok = check_scan_path(a, path, planar_oracle(0.3, 0.2, a), s);
  REQUIRE(ok.ok());
  CHECK(ok.joints.size() == 41);
  s.max_joint_step = worst * 0.999;
  // The first step whose change exceeds the bound, by the oracle.
  std::size_t first = 0;
  double first_value = 0.0;
  for (std::size_t i = 1; i <= 40 && first == 0; ++i) {
    const double d = (planar_oracle(0.3 + 0.01 * double(i), 0.2, a) -
                      planar_oracle(0.3 + 0.01 * double(i - 1), 0.2, a)).cwiseAbs().maxCoeff();
    if (d > s.max_joint_step) first = i, first_value = d;
  }
  REQUIRE(first == worst_step);
  const ScanPathReach bad = check_scan_path(a, path, planar_oracle(0.3, 0.2, a), s);
  REQUIRE_FALSE(bad.ok());
  CHECK(bad.failure == PathFailure::joint_jump);
  CHECK(bad.step == first);
  CHECK(bad.value == Approx(first_value).epsilon(1e-9));
  CHECK(bad.joints.size() == first);
}

TEST_CASE("check_scan_path: a joint leaving its limits is rejected", "[robot]") {
  PlanarArm a;
  a.ik_ignores_limits = true;  // a faulty IK: the check must still catch it
  a.limits.upper[0] = 0.6;
  const LinearScanPath path = planar_path(0.3, 0.7, 0.2);
  std::size_t first = 0;
  for (std::size_t i = 0; i <= 40 && first == 0; ++i)
    if (planar_oracle(0.3 + 0.01 * double(i), 0.2, a)[0] > 0.6) first = i;
  REQUIRE(first == 30);  // θ1 grows from −0.061 (x = 0.3) past 0.6 at x = 0.6 (0.609) to 0.870 (x = 0.7)
  ScanPathReachSetting s;
  s.max_joint_step = 1.0;
  const ScanPathReach r = check_scan_path(a, path, planar_oracle(0.3, 0.2, a), s);
  REQUIRE_FALSE(r.ok());
  CHECK(r.failure == PathFailure::joint_limit);
  CHECK(r.step == first);
  CHECK(r.joint == 0);
  CHECK(r.value == Approx(0.60877).margin(1e-4));
}

TEST_CASE("check_scan_path: the configuration check is the extension point", "[robot]") {
  const PlanarArm a;
  const LinearScanPath path = planar_path(0.3, 0.7, 0.2);
  ScanPathReachSetting s;
  s.max_joint_step = 1.0;
  // Refuse any sensor position beyond x = 0.505: samples 0..20 have x ≤ 0.5, sample 21 (x = 0.51) is refused.
  const auto beyond = [](const JointVector&, const Pose& T) { return T.translation().x() <= 0.505; };
  const ScanPathReach r = check_scan_path(a, path, planar_oracle(0.3, 0.2, a), s, beyond);
  CHECK(r.failure == PathFailure::configuration_rejected);
  CHECK(r.step == 21);
  CHECK(to_string(r.failure) == "configuration_rejected");
}

TEST_CASE("check_scan_path: a single viewpoint, and bad input", "[robot]") {
  const PlanarArm a;
  const LinearScanPath point(Viewpoint(planar_path(0.4, 0.4, 0.2).start()));
  const ScanPathReach one = check_scan_path(a, point, planar_oracle(0.4, 0.2, a));
  CHECK(one.ok());
  CHECK(one.samples == 1);
  CHECK(one.joints.size() == 1);
  const LinearScanPath path = planar_path(0.3, 0.7, 0.2);
  ScanPathReachSetting s;
  s.max_sample_step_m = 0.0;
  CHECK_THROWS_WITH(check_scan_path(a, path, jv(0, 0, 0), s), nbs_test::Contains("max_sample_step_m"));
  s = {};
  s.max_joint_step = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_WITH(check_scan_path(a, path, jv(0, 0, 0), s), nbs_test::Contains("max_joint_step"));
  CHECK_THROWS_WITH(check_scan_path(a, path, JointVector::Zero(2)), nbs_test::Contains("seed has 2 entries"));
  CHECK_THROWS_AS(check_scan_path(a, path, jv(0, std::numeric_limits<double>::infinity(), 0)), InvalidArgument);
}

TEST_CASE("JointLimits::validate names the joint and the values", "[robot]") {
  JointLimits l = PlanarArm::default_limits();
  CHECK_NOTHROW(l.validate());
  l.lower[1] = 1.0;
  l.upper[1] = 0.5;
  CHECK_THROWS_WITH(l.validate("arm"), nbs_test::Contains("arm: joint 1 has limits [1, 0.5]"));
  l.upper[1] = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_AS(l.validate(), InvalidArgument);
}

TEST_CASE("hemisphere_reach and require_object_in_reach", "[robot]") {
  const Vec3 centre(0, 0, 0.08);
  const HemisphereReach all = hemisphere_reach(FreeFlyingSensor{}, centre, 0.3, JointVector::Zero(6));
  CHECK(all.total == 49);
  CHECK(all.reachable == 49);
  CHECK_NOTHROW(require_object_in_reach(FreeFlyingSensor{}, centre, 0.3, JointVector::Zero(6), 1.0));
  // The planar arm reaches at most 0.8 m from its base: an object 5 m away is refused, naming the share.
  const PlanarArm a;
  CHECK(hemisphere_reach(a, Vec3(5, 0, 0), 0.3, jv(0, 0, 0)).reachable == 0);
  CHECK_THROWS_WITH(require_object_in_reach(a, Vec3(5, 0, 0), 0.3, jv(0, 0, 0)),
                    nbs_test::Contains("out of the robot's reach: 0 of 49 viewpoints at standoff"));
  // In its plane and in reach, the viewpoints at azimuth 0° and 180° and straight above are found (roll 270°
  // aligns the sensor's y with the arm's axis +y); the others leave the plane.
  const HemisphereReach planar = hemisphere_reach(a, Vec3(0.2, 0, 0.1), 0.3, jv(0.5, 0.5, 0.5));
  CHECK(planar.reachable > 0);
  CHECK(planar.reachable <= 9);
  CHECK_THROWS_AS(hemisphere_reach(a, centre, 0.0, jv(0, 0, 0)), InvalidArgument);
  CHECK_THROWS_AS(require_object_in_reach(a, centre, 0.3, jv(0, 0, 0), 0.0), InvalidArgument);
}
