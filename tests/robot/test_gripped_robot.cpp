// SPDX-License-Identifier: BSD-3-Clause
// GrippedRobot (gripped/gripped_robot.hpp): an arm holding the object as a Robot in the object frame O. Oracles:
// hand-computed Eq. 5.1 transforms (FreeFlyingSensor as the arm: arm.fk(q) = T_BO exactly), the planar arm's reach
// (0.8 m), brute-force 4 × 4 matrix inverses for the shapes, object_path_for for a sampled scan path.

#include "nbs_catch.hpp"

#include <Eigen/LU>

#include <cmath>
#include <numbers>

#include "conformance/robot_conformance.hpp"
#include "nbs/gripped/gripped_robot.hpp"
#include "nbs/robot/free_flying.hpp"
#include "nbs/robot/reachability.hpp"
#include "planar_robot.hpp"
#include "nbs_pose.hpp"

using nbs_test::rigid_pose;

using namespace nbs;
using nbs_test::Contains;

namespace {

Mat3 rot_y(double a) { return Eigen::AngleAxisd(a, Vec3::UnitY()).toRotationMatrix(); }
const Mat3 kGripRz90 = (Mat3() << 0, -1, 0, 1, 0, 0, 0, 0, 1).finished();

// The planar arm reaches up to 0.8 m from B's origin in the x-z plane; the sensor 1.3 m up, looking down (R_y(π)).
const Pose kTBSPlanar = rigid_pose(rot_y(std::numbers::pi), Vec3(0, 0, 1.3));

PlacedShape sensor_box() {
  PlacedShape s;
  s.link = "fixed sensor";
  s.shape.size = Vec3(0.1, 0.06, 0.08);
  s.T_WG = rigid_pose(rot_y(std::numbers::pi), Vec3(0, 0, 1.35));
  return s;
}

}  // namespace

TEST_CASE("GrippedRobot: fk and ik are Eq. 5.1 (hand-computed, free-flying arm)", "[robot][gripped]") {
  // T_BS: R_z(90°), (0.6, 0, 0.8). Arm at q = (0.1, 0.2, 0.3, 0, 0, 0): T_BO = I, (0.1, 0.2, 0.3).
  // T_OS = T_BO⁻¹ · T_BS = R_z(90°), (0.5, −0.2, 0.5).
  const GrippedRobot<FreeFlyingSensor> r(FreeFlyingSensor{}, rigid_pose(kGripRz90, Vec3(0.6, 0, 0.8)));
  JointVector q(6);
  q << 0.1, 0.2, 0.3, 0, 0, 0;
  const Pose T_OS = r.fk(q);
  CHECK((T_OS.translation() - Vec3(0.5, -0.2, 0.5)).norm() < 1e-12);
  CHECK((T_OS.linear() - kGripRz90).norm() < 1e-12);
  CHECK(r.hand_eye().matrix() == rigid_pose(kGripRz90, Vec3(0.6, 0, 0.8)).matrix());  // fk = T_OB · hand_eye
  CHECK((r.object_pose(q).inverse(Eigen::Isometry) * r.hand_eye()).isApprox(T_OS, 1e-12));

  // ik of a sensor pose in O: T_OS' = R_z(90°), (0, 0, 0.5) → T_BO = T_BS · T_OS'⁻¹ = I, (0.6, 0, 0.3).
  const auto s = r.ik(rigid_pose(kGripRz90, Vec3(0, 0, 0.5)), JointVector::Zero(6));
  REQUIRE(s);
  CHECK((s->head<3>() - Vec3(0.6, 0, 0.3)).norm() < 1e-12);
  CHECK(s->tail<3>().norm() < 1e-12);
  CHECK(poses_agree(r.fk(*s), rigid_pose(kGripRz90, Vec3(0, 0, 0.5)), 1e-12, 1e-12));
}

TEST_CASE("GrippedRobot: an object pose beyond the arm's reach is rejected, one within is solved", "[robot][gripped]") {
  const GrippedRobot<test::PlanarArm> r(test::PlanarArm{}, kTBSPlanar);
  const JointVector seed = JointVector::Constant(3, 0.1);
  // Sensor 0.6 m above the object: T_BO = T_BS · T_OS⁻¹ = I, (0, 0, 0.7), within 0.8 m.
  const Pose near = rigid_pose(rot_y(std::numbers::pi), Vec3(0, 0, 0.6));
  const auto q = r.ik(near, seed);
  REQUIRE(q);
  CHECK((r.object_pose(*q).translation() - Vec3(0, 0, 0.7)).norm() < 1e-9);
  CHECK(poses_agree(r.fk(*q), near, 1e-9, 1e-9));
  // Sensor 0.2 m above: the object at z = 1.1 m, 0.3 m beyond the arm's 0.8 m.
  const Pose far = rigid_pose(rot_y(std::numbers::pi), Vec3(0, 0, 0.2));
  CHECK_FALSE(r.ik(far, seed));
  // A scan path in O from the reachable pose towards the unreachable one fails where the object leaves the reach
  // (z_BO = 1.3 − z_OS > 0.8 m, i.e. z_OS < 0.5 m: t > 0.25 on the path 0.6 → 0.2 m). The joint-jump bound is
  // lifted: near full stretch the elbow moves fast, which is not what this checks.
  const LinearScanPath path(Viewpoint(near), far.translation());
  ScanPathReachSetting no_jump;
  no_jump.max_joint_step = 10.0;
  const ScanPathReach rep = check_scan_path(r, path, seed, no_jump);
  CHECK(rep.failure == PathFailure::unreachable);
  CHECK(rep.value >= 0.25 - 1e-9);
  CHECK(rep.value < 0.25 + 0.01 / 0.4 + 1e-9);  // the first sample after t = 0.25 (10 mm steps on 0.4 m)
}

TEST_CASE("GrippedRobot: a linear sensor path in O is the object's inverse linear path in B", "[robot][gripped]") {
  const Pose T_BS = rigid_pose(kGripRz90, Vec3(0.6, 0, 0.8));
  const GrippedRobot<FreeFlyingSensor> r(FreeFlyingSensor{}, T_BS);
  const Pose start = rigid_pose(Eigen::AngleAxisd(0.4, Vec3(1, 2, 3).normalized()).toRotationMatrix(), Vec3(0.1, 0, 0.3));
  const LinearScanPath path(Viewpoint(start), Vec3(-0.05, 0.1, 0.3));
  const ScanPathReach rep = check_scan_path(r, path, JointVector::Zero(6));
  REQUIRE(rep.ok());
  REQUIRE(rep.joints.size() == rep.samples);
  const ObjectPath op = object_path_for(T_BS, path);
  for (std::size_t i = 0; i < rep.samples; ++i) {
    const double t = static_cast<double>(i) / static_cast<double>(rep.samples - 1);
    const Pose T_BO = r.object_pose(rep.joints[i]);
    INFO("sample " << i);
    CHECK((T_BO.translation() - ((1 - t) * op.start.translation() + t * op.end.translation())).norm() < 1e-12);
    CHECK(rotation_angle_between(T_BO, op.start) < 1e-9);
    if (i > 0) CHECK((T_BO.translation() - r.object_pose(rep.joints[i - 1]).translation()).norm() <= 0.01 + 1e-12);
  }
}

TEST_CASE("GrippedRobot passes the Robot conformance suite (free-flying and planar arms)", "[robot][gripped]") {
  conformance::RobotCase c;
  c.samples = 30;
  const auto ff = conformance::check_robot_conformance(
      GrippedRobot<FreeFlyingSensor>(FreeFlyingSensor{}, rigid_pose(kGripRz90, Vec3(0.6, 0, 0.8))), c);
  CHECK(ff.ik_solved == ff.ik_tried);
  const auto pl = conformance::check_robot_conformance(
      GrippedRobot<test::PlanarArm>(test::PlanarArm{}, kTBSPlanar, {"link3"}, {sensor_box()}), c);
  CHECK(pl.ik_solved == pl.ik_tried);
}

TEST_CASE("GrippedRobot: collision shapes in O equal brute-force transforms, attached links left out",
          "[robot][gripped]") {
  const test::PlanarArm arm;
  const GrippedRobot<test::PlanarArm> r(arm, kTBSPlanar, {"link3"}, {sensor_box()});
  for (const Eigen::Vector3d& q3 : {Eigen::Vector3d(0.3, -0.5, 0.9), Eigen::Vector3d(-1, 1.2, 0)}) {
    const JointVector q = q3;
    const Eigen::Matrix4d M_OB = arm.fk(q).matrix().inverse();  // general 4 × 4 inverse
    const std::vector<PlacedShape> arm_shapes = arm.collision_shapes(q);
    const std::vector<PlacedShape> got = r.collision_shapes(q);
    REQUIRE(arm_shapes.size() == 3);
    REQUIRE(got.size() == 3);  // link1, link2, the sensor; link3 attached
    for (std::size_t i = 0; i < 2; ++i) {
      CHECK(got[i].link == arm_shapes[i].link);
      CHECK((got[i].T_WG.matrix() - M_OB * arm_shapes[i].T_WG.matrix()).norm() < 1e-12);
      CHECK(got[i].shape.radius == arm_shapes[i].shape.radius);
    }
    CHECK(got[2].link == "fixed sensor");
    CHECK((got[2].T_WG.matrix() - M_OB * sensor_box().T_WG.matrix()).norm() < 1e-12);
    CHECK(got[2].shape.size == sensor_box().shape.size);
  }
}

TEST_CASE("GrippedRobot: bad input names the value", "[robot][gripped]") {
  Pose scaled = kTBSPlanar;
  scaled.linear() *= 1.01;
  CHECK_THROWS_WITH(GrippedRobot<test::PlanarArm>(test::PlanarArm{}, scaled), Contains("T_BS"));
  CHECK_THROWS_WITH(GrippedRobot<test::PlanarArm>(test::PlanarArm{}, kTBSPlanar, {"gripper"}), Contains("'gripper'"));
  PlacedShape unnamed = sensor_box();
  unnamed.link.clear();
  CHECK_THROWS_AS(GrippedRobot<test::PlanarArm>(test::PlanarArm{}, kTBSPlanar, {}, {unnamed}), InvalidArgument);
  PlacedShape skewed = sensor_box();
  skewed.T_WG.linear() *= 2.0;
  CHECK_THROWS_WITH(GrippedRobot<test::PlanarArm>(test::PlanarArm{}, kTBSPlanar, {}, {skewed}),
                    Contains("fixed sensor"));
  const GrippedRobot<test::PlanarArm> r(test::PlanarArm{}, kTBSPlanar);
  Pose bad = rigid_pose(rot_y(std::numbers::pi), Vec3(0, 0, 0.6));
  bad.linear() *= 1.5;
  CHECK_THROWS_WITH(r.ik(bad, JointVector::Zero(3)), Contains("T_OS"));
}
