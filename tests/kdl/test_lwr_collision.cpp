// SPDX-License-Identifier: BSD-3-Clause
// The shipped LWR-class arm (data/robots/lwr4.urdf) against a bunny-sized box of unknown voxels (issue 19, item 2):
// collision-free along a standard scan path beside it, the forearm driven through it collides; timing of one check.
#include "nbs_catch.hpp"

#include <Eigen/Geometry>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>

#include "nbs/kdl/urdf_robot.hpp"
#include "nbs/robot/link_collision.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"
#include "lwr_fixture.hpp"

using namespace nbs;
using nbs::kdl::UrdfRobot;

namespace {

using std::numbers::pi;
// The unknown area around a bunny-sized object on the pedestal: 0.16 × 0.16 × 0.16 m, every voxel unknown.
const Aabb kBunnyBox{Vec3(-0.08, -0.08, 0.0), Vec3(0.08, 0.08, 0.16)};

using nbs_test::lwr;
using nbs_test::joints;
LinkCollisionSetting lwr_setting() {
  LinkCollisionSetting s;
  s.table_exempt_links = {"lwr_base_link"};  // stands on the table at z = 0 by design
  return s;
}
// The standard scan of tests/kdl/test_urdf_robot.cpp: looking at (0, 0, 0.08) from 0.3 m, 50° above the horizon,
// azimuth 135°, a 0.16 m stripe scan along the sensor's y centred there.
LinearScanPath standard_scan() {
  const Vec3 centre(0, 0, 0.08);
  const double e = 50 * pi / 180, az = 135 * pi / 180;
  const Vec3 eye = centre + 0.3 * Vec3(std::cos(e) * std::cos(az), std::cos(e) * std::sin(az), std::sin(e));
  const Vec3 z = (centre - eye).normalized();
  const Vec3 x = Vec3::UnitZ().cross(z).normalized();
  Pose start = Pose::Identity();
  start.linear() << x, z.cross(x), z;
  start.translation() = eye - 0.08 * start.linear().col(1);
  return LinearScanPath(Viewpoint(start), start.translation() + 0.16 * start.linear().col(1));
}
// True if the segment a–b passes through the box (sampled every 0.1 mm).
bool segment_enters(const Vec3& a, const Vec3& b, const Aabb& box) {
  for (int i = 0; i <= 10000; ++i) {
    const Vec3 p = a + (b - a) * (i / 10000.0);
    if ((p.array() >= box.min.array()).all() && (p.array() <= box.max.array()).all()) return true;
  }
  return false;
}

}  // namespace

TEST_CASE("lwr4.urdf beside a bunny-sized box of unknown voxels: the standard scan is collision-free, the forearm "
          "through the box collides",
          "[kdl][collision]") {
  const UrdfRobot r = lwr();
  const JointVector home = joints({0, 0.6, 0, -1.2, 0, 0.9, 0});
  const ProbabilisticVoxelSpace<> space(0.005, kBunnyBox);
  const RobotPathChecker checker(r, space, lwr_setting());

  const LinearScanPath path = standard_scan();
  const ScanPathReach run = checker.check(path, home);
  INFO("failure " << to_string(run.failure) << " at step " << run.step << " link " << run.link);
  REQUIRE(run.ok());
  REQUIRE(run.samples >= 17);
  // Independent of the checker: the sensor's optical centre stays ≥ 0.15 m from the box along the path.
  for (const JointVector& q : run.joints) {
    const Vec3 p = r.fk(q).translation();
    CHECK((p - p.cwiseMax(kBunnyBox.min).cwiseMin(kBunnyBox.max)).norm() >= 0.15);
  }

  // Upper arm leaning towards the object (A2 = −1.5), elbow bent down (A4 = 0.83): links 4–5 (the forearm) point
  // from above the box's corner through its inside.
  const JointVector through = joints({0, -1.5, 0, 0.83, 0, 0, 0});
  bool forearm_inside = false;
  for (const PlacedShape& s : r.collision_shapes(through))
    if (s.link == "lwr_link_5") {
      const Vec3 axis = 0.5 * s.shape.length * s.T_WG.linear().col(2);
      forearm_inside = segment_enters(s.T_WG.translation() - axis, s.T_WG.translation() + axis, kBunnyBox);
    }
  REQUIRE(forearm_inside);
  const auto hit = checker.links().first_contact(through);
  REQUIRE(hit);
  CHECK((hit->link == "lwr_link_4" || hit->link == "lwr_link_5"));
  CHECK(hit->with == LinkContact::With::voxel);
  CHECK(kBunnyBox.min.x() - 0.01 <= space.grid().center(hit->voxel).x());
  // The box is all unknown: with unknown space not counted no voxel is hit; the sensor, continuing the forearm's
  // line below the box, is then under the table top.
  LinkCollisionSetting observed_only = lwr_setting();
  observed_only.unknown_is_obstacle = false;
  const auto below = LinkCollisionChecker(r, space, observed_only).first_contact(through);
  REQUIRE(below);
  CHECK(below->with == LinkContact::With::table);
  observed_only.check_table = false;
  CHECK_FALSE(LinkCollisionChecker(r, space, observed_only).collides(through));
  // Without the base exempt, the base standing on the table (its bottom at z = 0 with a 1 mm margin) collides.
  LinkCollisionSetting strict;
  strict.safety_margin_m = 0.001;
  const auto base = LinkCollisionChecker(r, space, strict).first_contact(run.joints.front());
  REQUIRE(base);
  CHECK(base->link == "lwr_base_link");
  CHECK(base->with == LinkContact::With::table);
}

TEST_CASE("lwr4.urdf: time of one link check against the bunny-sized unknown box", "[kdl][collision][timing]") {
  const UrdfRobot r = lwr();
  const JointVector home = joints({0, 0.6, 0, -1.2, 0, 0.9, 0});
  const JointVector through = joints({0, -1.5, 0, 0.83, 0, 0, 0});
  const LinearScanPath path = standard_scan();
  using Clock = std::chrono::steady_clock;
  const auto us_per = [](Clock::time_point a, Clock::time_point b, int n) {
    return std::chrono::duration<double, std::micro>(b - a).count() / n;
  };
  for (const double l : {0.005, 0.002}) {
    const ProbabilisticVoxelSpace<> space(l, kBunnyBox);
    const RobotPathChecker checker(r, space, lwr_setting());
    LinkCollisionSetting observed_only = lwr_setting();
    observed_only.unknown_is_obstacle = false;
    observed_only.check_table = false;
    const LinkCollisionChecker scan_all(r, space, observed_only);
    const ScanPathReach run = checker.check(path, home);
    REQUIRE(run.ok());
    const int n = 200;
    int collisions = 0;
    const auto t0 = Clock::now();
    for (int i = 0; i < n; ++i)
      collisions += checker.links().collides(run.joints[static_cast<std::size_t>(i) % run.samples]);
    const auto t1 = Clock::now();
    // The forearm through the box with unknown voxels not counted: every voxel near the links inside the box is
    // tested and none is an obstacle (the most work one check does in this space).
    for (int i = 0; i < 20; ++i) collisions += scan_all.collides(through);
    const auto t2 = Clock::now();
    for (int i = 0; i < 5; ++i) REQUIRE(checker.check(path, home).ok());
    const auto t3 = Clock::now();
    CHECK(collisions == 0);
    std::printf("lwr link check, %.3f m voxels: beside the box %.1f us per configuration; forearm through the box, "
                "no obstacle (worst case) %.1f us; scan path of %zu samples with IK and link checks %.2f ms\n",
                l, us_per(t0, t1, n), us_per(t1, t2, 20), run.samples, us_per(t2, t3, 5) / 1000.0);
  }
}
