// SPDX-License-Identifier: BSD-3-Clause
// nbs::kdl::UrdfRobot on the shipped LWR-class arm (data/robots/lwr4.urdf): forward kinematics against poses computed
// by hand from the URDF's numbers, IK round trips, unreachable poses and paths, bad URDF files, conformance.
#include "nbs_catch.hpp"

#include <Eigen/Geometry>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <string>
#include <thread>

#include "conformance/robot_conformance.hpp"
#include "nbs/kdl/urdf_robot.hpp"
#include "nbs/robot/reachability.hpp"
#include "lwr_fixture.hpp"
#include "nbs_pose.hpp"

using nbs_test::rigid_pose;

using namespace nbs;
using nbs::kdl::UrdfRobot;

namespace {

const std::filesystem::path& kUrdf = nbs_test::kLwrUrdf;
using std::numbers::pi;
// The URDF's numbers: base at (−0.65, 0, 0) in the world (mount joint); A2 0.31 m above the base, A4 0.4 m above
// A2, A6 0.39 m above A4, the flange 0.078 m above A6; the sensor at (0.05, 0, 0.10) in the flange frame, rotated
// 90° about z.
const Vec3 kBase(-0.65, 0.0, 0.0);

using nbs_test::lwr;

Mat3 ry(double a) { return Eigen::AngleAxisd(a, Vec3::UnitY()).toRotationMatrix(); }
Mat3 rz(double a) { return Eigen::AngleAxisd(a, Vec3::UnitZ()).toRotationMatrix(); }
using nbs_test::joints;

// Writes `text` to a temporary URDF file and returns its path.
std::filesystem::path temp_urdf(const std::string& name, const std::string& text) {
  const auto p = std::filesystem::temp_directory_path() / ("nbs_test_kdl_" + name + ".urdf");
  std::ofstream(p) << text;
  return p;
}
std::string shipped_text() {
  std::ifstream in(kUrdf);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}
std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  REQUIRE(at != std::string::npos);
  return s.replace(at, from.size(), to);
}

// The sensor looking at `target` from `eye`, rolled by `roll` about its viewing direction.
Pose look_at(const Vec3& eye, const Vec3& target, double roll) {
  const Vec3 z = (target - eye).normalized();
  const Vec3 helper = std::abs(z.z()) > 0.9 ? Vec3::UnitX() : Vec3::UnitZ();
  const Vec3 x = helper.cross(z).normalized();
  return rigid_pose((Mat3() << x, z.cross(x), z).finished() * rz(roll), eye);
}

}  // namespace

TEST_CASE("lwr4.urdf: the chain, limits and hand-eye transform as written", "[kdl]") {
  const UrdfRobot r = lwr();
  REQUIRE(r.joint_count() == 7);
  CHECK(r.joint_names() == std::vector<std::string>{"lwr_a1", "lwr_a2", "lwr_a3", "lwr_a4", "lwr_a5", "lwr_a6",
                                                     "lwr_a7"});
  const double d170 = 170.0 * pi / 180.0, d120 = 120.0 * pi / 180.0;
  const JointVector upper = joints({d170, d120, d170, d120, d170, d120, d170});
  CHECK((r.joint_limits().upper - upper).cwiseAbs().maxCoeff() < 1e-9);
  CHECK((r.joint_limits().lower + upper).cwiseAbs().maxCoeff() < 1e-9);
  CHECK(poses_agree(r.hand_eye(), rigid_pose(rz(pi / 2), Vec3(0.05, 0, 0.10)), 1e-12, 1e-12));
  CHECK(poses_agree(r.base_pose(), Pose::Identity(), 0, 0));
}

TEST_CASE("lwr4.urdf: forward kinematics against hand-computed poses", "[kdl]") {
  const UrdfRobot r = lwr();
  const Vec3 a2 = kBase + Vec3(0, 0, 0.31), a4 = a2 + Vec3(0, 0, 0.4);
  const Pose T_FS = rigid_pose(rz(pi / 2), Vec3(0.05, 0, 0.10));
  struct Case {
    const char* what;
    JointVector q;
    Pose T_WF;
  };
  const std::vector<Case> cases{
      // Straight up: the flange 0.31 + 0.4 + 0.39 + 0.078 = 1.178 m above the base.
      {"zero", JointVector::Zero(7), rigid_pose(Mat3::Identity(), kBase + Vec3(0, 0, 1.178))},
      // A2 (axis −y) at +90°: the arm above A2 turns by R_y(−90°) and points along −x.
      {"A2 = 90°", joints({0, pi / 2, 0, 0, 0, 0, 0}), rigid_pose(ry(-pi / 2), a2 + Vec3(-0.868, 0, 0))},
      // A4 (axis +y) at +90°: the forearm points along +x from A4.
      {"A4 = 90°", joints({0, 0, 0, pi / 2, 0, 0, 0}), rigid_pose(ry(pi / 2), a4 + Vec3(0.468, 0, 0))},
      // A1 = 90° turns that about the base's z axis: the forearm points along +y.
      {"A1 = A4 = 90°", joints({pi / 2, 0, 0, pi / 2, 0, 0, 0}),
       rigid_pose(rz(pi / 2) * ry(pi / 2), a4 + Vec3(0, 0.468, 0))},
      // A7 = 90°: only the flange turns about its z axis.
      {"A7 = 90°", joints({0, 0, 0, 0, 0, 0, pi / 2}), rigid_pose(rz(pi / 2), kBase + Vec3(0, 0, 1.178))},
      // A5 = 90° turns the wrist about z; A6 (axis −y) at −90° is then R_y(+90°) in the turned frame:
      // R = R_z(90°) R_y(90°), whose z axis is +y, so the flange is 0.078 m from A6 (1.10 m up) along +y.
      {"A5 = 90°, A6 = −90°", joints({0, 0, 0, 0, pi / 2, -pi / 2, 0}),
       rigid_pose(rz(pi / 2) * ry(pi / 2), kBase + Vec3(0, 0.078, 1.10))},
  };
  for (const Case& c : cases) {
    INFO(c.what << "\nfk:\n" << r.fk(c.q).matrix() << "\nexpected T_WF:\n" << c.T_WF.matrix());
    CHECK(poses_agree(r.flange_pose(c.q), c.T_WF, 1e-12, 1e-12));
    CHECK(poses_agree(r.fk(c.q), c.T_WF * T_FS, 1e-12, 1e-12));
  }
  // One by hand in numbers: A4 = 90° puts the sensor at A4 + (0.468, 0, 0) + R_y(90°)(0.05, 0, 0.10)
  // = (−0.65 + 0.468 + 0.10, 0, 0.71 − 0.05) = (−0.082, 0, 0.66).
  CHECK((r.fk(joints({0, 0, 0, pi / 2, 0, 0, 0})).translation() - Vec3(-0.082, 0, 0.66)).norm() < 1e-12);
}

TEST_CASE("lwr4.urdf: collision shapes from the <collision> elements, placed by fk", "[kdl]") {
  const UrdfRobot r = lwr();
  const auto shapes = r.collision_shapes(JointVector::Zero(7));
  // world has none; base, links 1–5 (cylinders), link 6 (sphere), flange (cylinder), sensor (box).
  REQUIRE(shapes.size() == 9);
  CHECK(shapes.front().link == "lwr_base_link");
  CHECK(shapes.front().shape.kind == LinkShape::Kind::cylinder);
  CHECK((shapes.front().T_WG.translation() - (kBase + Vec3(0, 0, 0.055))).norm() < 1e-12);
  CHECK(shapes[6].link == "lwr_link_6");
  CHECK(shapes[6].shape.kind == LinkShape::Kind::sphere);
  CHECK((shapes[6].T_WG.translation() - (kBase + Vec3(0, 0, 1.10))).norm() < 1e-12);
  const PlacedShape& head = shapes.back();
  CHECK(head.link == "sensor");
  CHECK(head.shape.kind == LinkShape::Kind::box);
  CHECK((head.shape.size - Vec3(0.12, 0.06, 0.10)).norm() < 1e-12);
  // The sensor box hangs 0.05 m behind the optical centre along the sensor's −z.
  const Pose T_WS = r.fk(JointVector::Zero(7));
  CHECK((head.T_WG.translation() - (T_WS.translation() - 0.05 * T_WS.linear().col(2))).norm() < 1e-12);
}

TEST_CASE("UrdfRobot: IK round trips over random reachable poses, deterministic", "[kdl]") {
  const UrdfRobot r = lwr();
  std::mt19937_64 rng(42);
  const JointLimits lim = r.joint_limits();
  const JointVector home = joints({0, 0.6, 0, -1.2, 0, 0.9, 0});
  int solved = 0, tried = 0;
  double worst_p = 0, worst_a = 0, seconds = 0;
  for (int i = 0; i < 60; ++i) {
    const JointVector q = conformance::random_joints(lim, rng, pi);
    const Pose T = r.fk(q);
    const auto t0 = std::chrono::steady_clock::now();
    const auto s = r.ik(T, home);  // from a fixed home configuration: the restarts must find the far ones
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ++tried;
    if (!s) continue;
    ++solved;
    REQUIRE(lim.contains(*s));
    const Pose back = r.fk(*s);
    worst_p = std::max(worst_p, (back.translation() - T.translation()).norm());
    worst_a = std::max(worst_a, rotation_angle_between(back, T));
    CHECK(*r.ik(T, home) == *s);  // the same seed and settings give the same answer
  }
  std::printf("kdl ik from home: %d / %d solved, worst error %.3g m %.3g rad, %.3g ms per solve\n", solved, tried,
              worst_p, worst_a, 1e3 * seconds / tried);
  CHECK(solved >= tried * 95 / 100);
  CHECK(worst_p <= 1e-4);
  CHECK(worst_a <= 1.745e-3);

  // Another IK seed changes the restarts, not the validity.
  UrdfRobot other = r;
  kdl::IkSetting s = r.ik_setting();
  s.seed = 99;
  other.set_ik_setting(s);
  const Pose T = r.fk(joints({0.3, 0.8, -0.2, -1.0, 0.4, 0.7, 0.1}));
  const auto a = other.ik(T, home);
  REQUIRE(a);
  CHECK(poses_agree(r.fk(*a), T, 1e-4, 1.745e-3));
}

TEST_CASE("UrdfRobot: const members run concurrently with the sequential answers", "[kdl]") {
  const UrdfRobot r = lwr();
  std::mt19937_64 rng(5);
  const JointVector home = joints({0, 0.6, 0, -1.2, 0, 0.9, 0});
  std::vector<Pose> targets;
  for (int i = 0; i < 20; ++i) targets.push_back(r.fk(conformance::random_joints(r.joint_limits(), rng, pi)));
  std::vector<std::optional<JointVector>> seq, a(targets.size()), b(targets.size());
  for (const Pose& T : targets) seq.push_back(r.ik(T, home));
  std::thread t1([&] { for (std::size_t i = 0; i < targets.size(); ++i) a[i] = r.ik(targets[i], home); });
  std::thread t2([&] { for (std::size_t i = targets.size(); i-- > 0;) b[i] = r.ik(targets[i], home); });
  t1.join();
  t2.join();
  CHECK(a == seq);
  CHECK(b == seq);
}

TEST_CASE("UrdfRobot passes the Robot conformance suite", "[kdl]") {
  conformance::RobotCase c;
  c.samples = 30;
  c.unlimited_range = pi;
  const auto rep = conformance::check_robot_conformance(lwr(), c);
  CHECK(rep.ik_solved == rep.ik_tried);
}

TEST_CASE("UrdfRobot: poses beyond reach and behind the base have no IK solution", "[kdl]") {
  const UrdfRobot r = lwr();
  const JointVector home = joints({0, 0.6, 0, -1.2, 0, 0.9, 0});
  // The sensor is at most 0.4 + 0.39 + 0.078 + |(0.05, 0, 0.10)| = 0.98 m from A2 at (−0.65, 0, 0.31).
  const Vec3 a2 = kBase + Vec3(0, 0, 0.31);
  for (const Vec3& p : {Vec3(0.45, 0, 0.3), Vec3(-1.45, 0, -0.4), Vec3(-0.65, 0, 1.35)}) {
    INFO("target " << p.transpose() << ", " << (p - a2).norm() << " m from A2");
    REQUIRE((p - a2).norm() > 1.0);
    CHECK_FALSE(r.ik(look_at(p, Vec3(0, 0, 0.08), 0.0), home));
  }
}

TEST_CASE("check_scan_path on the LWR: a vertical scan beside the object is flown, one beyond reach is not",
          "[kdl]") {
  const UrdfRobot r = lwr();
  const JointVector home = joints({0, 0.6, 0, -1.2, 0, 0.9, 0});
  // Looking at the object's centre (0, 0, 0.08) from 0.3 m, 50° above the horizon, from azimuth 135° (the robot's
  // side, half turned away), a 0.16 m stripe scan along the sensor's y centred there.
  const Vec3 centre(0, 0, 0.08);
  const double e = 50 * pi / 180, az = 135 * pi / 180;
  Pose start = look_at(centre + 0.3 * Vec3(std::cos(e) * std::cos(az), std::cos(e) * std::sin(az), std::sin(e)), centre,
                       0.0);
  start.translation() -= 0.08 * start.linear().col(1);
  const LinearScanPath near(Viewpoint(start), start.translation() + 0.16 * start.linear().col(1));
  const ScanPathReach ok = check_scan_path(r, near, home);
  INFO("failure " << to_string(ok.failure) << " at step " << ok.step << " value " << ok.value);
  REQUIRE(ok.ok());
  REQUIRE(ok.joints.size() == ok.samples);
  REQUIRE(ok.samples >= 17);
  for (std::size_t i = 0; i < ok.joints.size(); ++i)
    CHECK(poses_agree(r.fk(ok.joints[i]), near.pose_at(double(i) / double(ok.samples - 1)), 1e-4, 1.745e-3));

  // Looking down, moving away from the base along +x (the sensor's y) at z = 0.5: the first sample more than 0.98 m
  // from A2 (x > 0.311) cannot be reached, so the path fails there at the latest.
  start.linear() = (Mat3() << Vec3(0, 1, 0), Vec3(1, 0, 0), Vec3(0, 0, -1)).finished();
  start.translation() = Vec3(-0.2, 0, 0.5);
  const LinearScanPath far(Viewpoint(start), Vec3(0.6, 0, 0.5));
  const ScanPathReach bad = check_scan_path(r, far, home);
  REQUIRE_FALSE(bad.ok());
  const Vec3 a2 = kBase + Vec3(0, 0, 0.31);
  std::size_t first_out = 0;
  while ((far.pose_at(double(first_out) / double(bad.samples - 1)).translation() - a2).norm() <= 0.98) ++first_out;
  CHECK(bad.step <= first_out);
  CHECK(bad.step > 0);
  CHECK((bad.failure == PathFailure::unreachable || bad.failure == PathFailure::joint_jump));
  std::printf("kdl path beyond reach: %s at step %zu of %zu (first sample beyond 0.98 m from A2: %zu)\n",
              std::string(to_string(bad.failure)).c_str(), bad.step, bad.samples, first_out);
}

TEST_CASE("lwr4.urdf: the object on the pedestal is reachable at 0.3 m standoff from much of the hemisphere",
          "[kdl]") {
  const UrdfRobot r = lwr();
  const JointVector home = joints({0, 0.6, 0, -1.2, 0, 0.9, 0});
  const Vec3 centre(0, 0, 0.08);  // an object 0.16 m tall on the pedestal
  const HemisphereReach h = hemisphere_reach(r, centre, 0.3, home);
  std::printf("kdl hemisphere at 0.3 m standoff: %d / %d viewpoints reachable (%.0f %%)\n", h.reachable, h.total,
              100.0 * h.share());
  CHECK(h.total == 49);
  CHECK(h.share() >= 0.5);
  CHECK_NOTHROW(require_object_in_reach(r, centre, 0.3, home));
  // The base 3 m away: no viewpoint is reachable, refused before any work with the measured share.
  Pose far = Pose::Identity();
  far.translation() = Vec3(-3.0, 0, 0);
  kdl::IkSetting few;
  few.restarts = 3;  // every attempt fails here; fewer keep the test short
  const UrdfRobot away = UrdfRobot::load(kUrdf, "world", "lwr_flange", "sensor", far, few);
  CHECK_THROWS_WITH(require_object_in_reach(away, centre, 0.3, home),
                    nbs_test::Contains("out of the robot's reach: 0 of 49 viewpoints at standoff"));
}

TEST_CASE("UrdfRobot without movable joints: the one sensor pose or nothing", "[kdl]") {
  const auto path = temp_urdf("fixed", R"(<robot name="fixed"><link name="b"/><link name="s"/>
    <joint name="m" type="fixed"><parent link="b"/><child link="s"/><origin xyz="0.1 0.2 0.3" rpy="0 0 0"/></joint>
    </robot>)");
  const UrdfRobot r = UrdfRobot::load(path, "b", "b", "s");
  std::filesystem::remove(path);
  CHECK(r.joint_count() == 0);
  const JointVector none(0);
  CHECK((r.fk(none).translation() - Vec3(0.1, 0.2, 0.3)).norm() < 1e-15);
  CHECK(r.ik(r.fk(none), none));
  CHECK_FALSE(r.ik(rigid_pose(Mat3::Identity(), Vec3(0, 0, 0)), none));
}

TEST_CASE("UrdfRobot::load: bad files and arguments give a clear error naming the file, link or value", "[kdl]") {
  const std::string urdf = shipped_text();
  using nbs_test::Contains;
  CHECK_THROWS_AS(UrdfRobot::load("/nonexistent/arm.urdf", "world", "lwr_flange", "sensor"), FileError);
  CHECK_THROWS_WITH(UrdfRobot::load("/nonexistent/arm.urdf", "world", "lwr_flange", "sensor"),
                    Contains("/nonexistent/arm.urdf"));
  const auto broken = temp_urdf("broken", urdf.substr(0, urdf.size() / 2));
  CHECK_THROWS_AS(UrdfRobot::load(broken, "world", "lwr_flange", "sensor"), FileError);
  CHECK_THROWS_WITH(UrdfRobot::load(broken, "world", "lwr_flange", "sensor"), Contains(broken.string()));
  CHECK_THROWS_WITH(UrdfRobot::load(kUrdf, "world", "tool0", "sensor"), Contains("flange link 'tool0' is not in"));
  CHECK_NOTHROW(UrdfRobot::load(kUrdf, "world", "lwr_flange", "sensor"));
  CHECK_THROWS_WITH(UrdfRobot::load(kUrdf, "lwr_link_3", "lwr_link_2", "sensor"),
                    Contains("flange link 'lwr_link_2' is not below base link 'lwr_link_3'"));
  CHECK_THROWS_WITH(UrdfRobot::load(kUrdf, "world", "lwr_flange", "lwr_link_3"),
                    Contains("sensor link 'lwr_link_3' is not on the chain below flange link 'lwr_flange'"));
  CHECK_THROWS_WITH(UrdfRobot::load(kUrdf, "world", "lwr_link_5", "sensor"),
                    Contains("joint 'lwr_a7' is not fixed"));
  const auto inverted = temp_urdf("inverted", replaced(urdf, R"(<limit lower="-2.0943951024" upper="2.0943951024")",
                                                       R"(<limit lower="1" upper="-1")"));
  CHECK_THROWS_WITH(UrdfRobot::load(inverted, "world", "lwr_flange", "sensor"),
                    Contains(inverted.string()) && Contains("lwr_a2") && Contains("[1, -1]"));
  const auto nan = temp_urdf("nan", replaced(urdf, R"(<limit lower="-2.0943951024")", R"(<limit lower="nan")"));
  CHECK_THROWS_WITH(UrdfRobot::load(nan, "world", "lwr_flange", "sensor"),
                    Contains(nan.string()) && Contains("lwr_a2") && Contains("nan"));
  Pose bad = Pose::Identity();
  bad.linear() *= 2.0;
  CHECK_THROWS_WITH(UrdfRobot::load(kUrdf, "world", "lwr_flange", "sensor", bad), Contains("T_WB"));
  kdl::IkSetting s;
  s.restarts = -1;
  CHECK_THROWS_WITH(UrdfRobot::load(kUrdf, "world", "lwr_flange", "sensor", Pose::Identity(), s),
                    Contains("restarts"));
  UrdfRobot r = lwr();
  CHECK_THROWS_AS(r.set_ik_setting(s), InvalidArgument);
  CHECK(r.ik_setting().restarts == kdl::IkSetting{}.restarts);  // unchanged
  CHECK_THROWS_AS(r.set_hand_eye(bad), InvalidArgument);
  CHECK(poses_agree(r.hand_eye(), rigid_pose(rz(pi / 2), Vec3(0.05, 0, 0.10)), 1e-12, 1e-12));
  const auto floating = temp_urdf("floating", replaced(urdf, R"(<joint name="lwr_a3" type="revolute">)",
                                                       R"(<joint name="lwr_a3" type="floating">)"));
  CHECK_THROWS_WITH(UrdfRobot::load(floating, "world", "lwr_flange", "sensor"),
                    Contains("joint 'lwr_a3' has a type nbs::kdl does not support"));
  const auto mimic = temp_urdf("mimic", replaced(urdf, R"(<child link="lwr_flange"/>)",
                                                 R"(<child link="lwr_flange"/><mimic joint="lwr_a5"/>)"));
  CHECK_THROWS_WITH(UrdfRobot::load(mimic, "world", "lwr_flange", "sensor"),
                    Contains("joint 'lwr_a7' mimics joint 'lwr_a5'"));
  for (const auto& p : {broken, inverted, nan, floating, mimic}) std::filesystem::remove(p);
}
