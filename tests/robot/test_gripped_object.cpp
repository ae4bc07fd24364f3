// SPDX-License-Identifier: BSD-3-Clause
// Gripped-object modeling (Sec. 5.4): Eq. 5.1 against hand-computed transforms, the data mapping back into the object
// frame, the finger filter against a brute-force closest-point oracle, and bad input (an object larger than its
// tool box, non-rigid poses) that throws and changes nothing.

#include "nbs_catch.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "nbs/driver/simulated_driver.hpp"
#include "nbs/gripped/gripped_driver.hpp"
#include "nbs/gripped/gripped_object.hpp"
#include "nbs/gripped/gripped_simulation.hpp"
#include "nbs/sensor/laser_stripe_profiler.hpp"
#include "nbs/sim/sphere_on_pedestal.hpp"
#include "nbs_pose.hpp"
#include "nbs_random.hpp"

using nbs_test::rigid_pose;

namespace {

using nbs::Mat3;
using nbs::Pose;
using nbs::Vec3;


void check_pose(const Pose& a, const Pose& b) {
  INFO("got\n" << a.matrix() << "\nexpected\n" << b.matrix());
  CHECK((a.matrix() - b.matrix()).cwiseAbs().maxCoeff() < 1e-12);
}

// Hand-computed: the fixed sensor at (1, 2, 0.5) in B, turned 90° about z (its viewing axis stays +z of B).
const Mat3 kRz90 = (Mat3() << 0, -1, 0, 1, 0, 0, 0, 0, 1).finished();
const Mat3 kRx180 = (Mat3() << 1, 0, 0, 0, -1, 0, 0, 0, -1).finished();
const Pose kTBS = rigid_pose(kRz90, Vec3(1, 2, 0.5));

nbs::PlacedShape box_finger(const char* name, const Pose& T_OG, const Vec3& size) {
  nbs::PlacedShape f;
  f.link = name;
  f.shape.kind = nbs::LinkShape::Kind::box;
  f.shape.size = size;
  f.T_WG = T_OG;
  return f;
}

nbs::GrippedSetup two_fingers() {
  nbs::GrippedSetup s;
  s.T_BS = kTBS;
  s.tool_box = {Vec3(-0.05, -0.05, 0.0), Vec3(0.05, 0.05, 0.2)};
  s.fingers.push_back(box_finger("left", rigid_pose(Mat3::Identity(), Vec3(-0.045, 0, 0.03)), Vec3(0.01, 0.02, 0.06)));
  s.fingers.push_back(box_finger("right",
                                 rigid_pose(Eigen::AngleAxisd(0.3, Vec3::UnitZ()).toRotationMatrix(),
                                           Vec3(0.045, 0, 0.03)),
                                 Vec3(0.01, 0.02, 0.06)));
  s.finger_margin_m = 0.002;
  return s;
}

}  // namespace

TEST_CASE("gripped object: Eq. 5.1 frame mapping against hand-computed transforms", "[gripped]") {
  // Sensor 0.3 m below the object origin in O, looking up (+z): the object is 0.3 m in front of the fixed sensor,
  // T_BO = [Rz90 | Rz90 (0, 0, 0.3) + (1, 2, 0.5)] = [Rz90 | (1, 2, 0.8)].
  check_pose(nbs::object_pose_for(kTBS, rigid_pose(Mat3::Identity(), Vec3(0, 0, -0.3))),
             rigid_pose(kRz90, Vec3(1, 2, 0.8)));
  // Sensor 0.4 m above the object in O looking down (Rx180): T_OS⁻¹ = [Rx180 | (0, 0, 0.4)], so
  // T_BO = [Rz90 Rx180 | (1, 2, 0.9)]: the object hangs upside down 0.4 m above the sensor.
  const Pose T_OS = rigid_pose(kRx180, Vec3(0, 0, 0.4));
  const Mat3 R_BO = (Mat3() << 0, 1, 0, 1, 0, 0, 0, 0, -1).finished();
  const Pose T_BO = rigid_pose(R_BO, Vec3(1, 2, 0.9));
  check_pose(nbs::object_pose_for(kTBS, T_OS), T_BO);
  check_pose(nbs::sensor_pose_in_object(kTBS, T_BO), T_OS);

  // A linear scan path 0.1 m along the sensor's y (in O: (0, −0.1, 0)): the object moves by −R_BO (0, −0.1, 0) =
  // (0.1, 0, 0) in B with a fixed orientation; halfway it is halfway.
  const nbs::LinearScanPath path(nbs::Viewpoint(T_OS), Vec3(0, -0.1, 0.4));
  const nbs::ObjectPath op = nbs::object_path_for(kTBS, path);
  check_pose(op.start, T_BO);
  check_pose(op.end, rigid_pose(R_BO, Vec3(1.1, 2, 0.9)));
  check_pose(nbs::object_pose_for(kTBS, path.pose_at(0.5)), rigid_pose(R_BO, Vec3(1.05, 2, 0.9)));

  // The data half: a point p_O = (0.01, 0.02, 0.03) on the object is seen in B at R_BO p_O + t = (1.02, 2.01, 0.87);
  // mapped back with the object pose of its profile it is p_O again, and the profile pose becomes T_OS.
  nbs::Scan scan_B;
  scan_B.profile_poses = {kTBS, kTBS};
  scan_B.add_point(Vec3(1.02, 2.01, 0.87), 0);
  scan_B.add_point(Vec3(1.12, 2.01, 0.87), 1);
  const nbs::Scan scan_O = nbs::scan_in_object_frame(scan_B, {op.start, op.end});
  CHECK((scan_O.points[0] - Vec3(0.01, 0.02, 0.03)).norm() < 1e-12);
  CHECK((scan_O.points[1] - Vec3(0.01, 0.02, 0.03)).norm() < 1e-12);  // the object moved by 0.1 m along x of B
  check_pose(scan_O.profile_poses[0], path.pose_at(0.0));
  check_pose(scan_O.profile_poses[1], path.pose_at(1.0));
}

TEST_CASE("gripped object: the finger filter removes exactly the points within the margin (brute force)",
          "[gripped]") {
  const nbs::GrippedSetup setup = two_fingers();
  // Oracle: distance to a box = distance to its closest point, clamp(p_G, −h, h) in the box frame (outside), or 0.
  const auto near_finger = [&](const Vec3& p) {
    for (const auto& f : setup.fingers) {
      const Vec3 g = f.T_WG.inverse(Eigen::Isometry) * p, h = 0.5 * f.shape.size;
      if ((g - g.cwiseMax(-h).cwiseMin(h)).norm() <= setup.finger_margin_m) return true;
    }
    return false;
  };
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-0.06, 0.06);
  nbs::Scan scan;
  scan.profile_poses = {rigid_pose(Mat3::Identity(), Vec3(0, 0, -0.3)),
                        rigid_pose(Mat3::Identity(), Vec3(0, 0.01, -0.3))};
  std::vector<Vec3> expected;
  std::vector<std::uint32_t> expected_profile;
  std::vector<nbs::Rgb> expected_colors;  // colours stay with their points
  for (int i = 0; i < 4000; ++i) {
    const Vec3 p = nbs_test::random_vec3(u, rng) + Vec3(0.0, 0.0, 0.03);
    const auto k = static_cast<std::uint32_t>(i % 2);
    const nbs::Rgb c{static_cast<std::uint8_t>(i % 256), static_cast<std::uint8_t>(i / 256), 7};
    scan.add_point(p, k, c);
    if (!near_finger(p)) expected.push_back(p), expected_profile.push_back(k), expected_colors.push_back(c);
  }
  const std::size_t removed = nbs::remove_finger_points(setup, scan);
  REQUIRE(removed > 100);  // the oracle's finger band is hit by the draw
  CHECK(removed + expected.size() == 4000);
  REQUIRE(scan.points == expected);
  CHECK(scan.profile_of_point == expected_profile);
  CHECK(scan.colors == expected_colors);
  CHECK(scan.profile_poses.size() == 2);
  CHECK_NOTHROW(scan.validate());
}

TEST_CASE("gripped object: bad input (an object larger than its box, non-rigid poses) throws and changes nothing",
          "[gripped]") {
  const nbs::GrippedSetup setup = two_fingers();
  // 0.12 m wide object in a 0.1 m wide tool box: both sizes named.
  const nbs::Aabb too_wide{Vec3(-0.06, -0.02, 0.0), Vec3(0.06, 0.02, 0.05)};
  CHECK_THROWS_WITH(nbs::require_object_in_tool_box(setup, too_wide),
                    nbs_test::Contains("larger than its tool box") && nbs_test::Contains("object 0.12") &&
                        nbs_test::Contains("tool box 0.1"));
  CHECK_NOTHROW(nbs::require_object_in_tool_box(setup, {Vec3(-0.04, -0.02, 0.0), Vec3(0.04, 0.02, 0.05)}));
  // The same check guards the simulated scene.
  nbs::IndexedMesh big;
  big.vertices = {Vec3(-0.06, 0, 0.01), Vec3(0.06, 0, 0.01), Vec3(0, 0.01, 0.02)};
  big.triangles = {{0, 1, 2}};
  CHECK_THROWS_WITH(nbs::gripped_scene_mesh(setup, big), nbs_test::Contains("larger than its tool box"));

  Pose nan_pose = kTBS;
  nan_pose(0, 3) = std::nan("");
  CHECK_THROWS_AS(nbs::object_pose_for(nan_pose, Pose::Identity()), nbs::InvalidArgument);
  CHECK_THROWS_AS(nbs::object_pose_for(kTBS, nan_pose), nbs::InvalidArgument);
  nbs::GrippedSetup bad = setup;
  bad.T_BS = nan_pose;
  CHECK_THROWS_WITH(bad.validate(), nbs_test::Contains("GrippedSetup.T_BS"));
  bad = setup;
  bad.finger_margin_m = -1.0;
  nbs::Scan scan;
  scan.profile_poses = {Pose::Identity()};
  scan.add_point(Vec3(-0.045, 0, 0.03), 0);  // inside the left finger
  CHECK_THROWS_WITH(nbs::remove_finger_points(bad, scan), nbs_test::Contains("finger_margin_m"));
  CHECK(scan.size() == 1);

  // The driver: a non-rigid planned pose throws before the inner driver moves; nothing is recorded.
  const nbs::SphereOnPedestal sphere;
  nbs::SimulatedDriver<nbs::SphereOnPedestal, nbs::LaserStripeProfiler> inner(sphere, nbs::LaserStripeProfiler{}, 1);
  nbs::GrippedDriver driver(inner, setup);
  const Pose before = driver.current_pose();
  CHECK_THROWS_AS(driver.move_to(nan_pose), nbs::InvalidArgument);
  CHECK(driver.current_pose().isApprox(before));
  CHECK(driver.object_paths().empty());
  CHECK(nbs::GrippedDriver<decltype(inner)>(inner, setup).removed_points() == 0);
  CHECK_THROWS_AS(nbs::GrippedDriver<decltype(inner)>(inner, bad), nbs::InvalidArgument);
}
