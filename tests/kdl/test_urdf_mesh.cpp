// SPDX-License-Identifier: BSD-3-Clause
// UrdfRobot with mesh <collision> elements (issue 19, item 1): a URDF in a temporary package directory whose links'
// meshes are found by package:// (the URDF's ancestor, given roots, ROS_PACKAGE_PATH), relative and file:// paths,
// loaded once with the URDF scale and placed by fk; against LinkCollisionChecker the mesh link gives the same
// contacts as the same link written as a <box>; missing and malformed meshes give errors naming link and file.
#include "nbs_catch.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <utility>

#include <unistd.h>

#include "nbs/io/read_stl.hpp"
#include "nbs/kdl/urdf_robot.hpp"
#include "nbs/robot/link_collision.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"
#include "sim/test_meshes.hpp"

using namespace nbs;
using nbs::kdl::UrdfRobot;
using nbs_test::Contains;
namespace fs = std::filesystem;

namespace {

const Vec3 kBox(0.1, 0.06, 0.04);  // the mesh file's box, centred at its origin

/// Restores an environment variable (its value, or its absence) when it dies.
struct EnvRestore {
  std::string name;
  std::optional<std::string> value;
  explicit EnvRestore(std::string n) : name(std::move(n)) {
    if (const char* v = std::getenv(name.c_str())) value = v;
  }
  EnvRestore(const EnvRestore&) = delete;
  EnvRestore& operator=(const EnvRestore&) = delete;
  ~EnvRestore() {
    if (value) ::setenv(name.c_str(), value->c_str(), 1);
    else ::unsetenv(name.c_str());
  }
};

// <ws>/meshpkg/{urdf/arm.urdf, meshes/box.stl (binary), meshes/box_ascii.stl}: base link = the box mesh scaled
// (2, 1, 1) through package://, 5 cm up; link "arm" (revolute j1 about z, 0.1 m above the base) = the ASCII box
// through a relative path at (0.2, 0, 0) rotated 0.3 rad about z. `base_mesh` / `arm_mesh` replace the references.
struct Package {
  fs::path ws = fs::temp_directory_path() / ("nbs_test_kdl_mesh_ws_" + std::to_string(::getpid()));
  fs::path urdf = ws / "meshpkg" / "urdf" / "arm.urdf";
  explicit Package(const std::string& base_mesh = "package://meshpkg/meshes/box.stl",
                   const std::string& arm_mesh = "../meshes/box_ascii.stl", const std::string& box_or_mesh = "") {
    fs::create_directories(ws / "meshpkg" / "urdf");
    fs::create_directories(ws / "meshpkg" / "meshes");
    const IndexedMesh box = test::box_mesh(-0.5 * kBox, 0.5 * kBox);
    write_stl((ws / "meshpkg" / "meshes" / "box.stl").string(), box, StlFormat::binary);
    write_stl((ws / "meshpkg" / "meshes" / "box_ascii.stl").string(), box, StlFormat::ascii);
    const std::string arm_geometry =
        box_or_mesh.empty() ? R"(<mesh filename=")" + arm_mesh + R"("/>)" : box_or_mesh;
    std::ofstream(urdf) << R"(<robot name="m">
  <link name="base"><collision><origin xyz="0 0 0.05"/>
    <geometry><mesh filename=")" << base_mesh << R"(" scale="2 1 1"/></geometry></collision></link>
  <link name="arm"><collision><origin xyz="0.2 0 0" rpy="0 0 0.3"/><geometry>)"
                        << arm_geometry << R"(</geometry></collision></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="arm"/><origin xyz="0 0 0.1"/>
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
</robot>)";
  }
  Package(const Package&) = delete;
  Package& operator=(const Package&) = delete;
  ~Package() {
    std::error_code ec;
    fs::remove_all(ws, ec);
  }
};

UrdfRobot load(const fs::path& urdf, const std::vector<fs::path>& roots = {}) {
  return UrdfRobot::load(urdf, "base", "arm", "arm", Pose::Identity(), {}, roots);
}

}  // namespace

TEST_CASE("UrdfRobot: mesh collision elements are loaded once (package://, relative), scaled and placed by fk",
          "[kdl][mesh]") {
  const Package pkg;
  const UrdfRobot r = load(pkg.urdf);  // package://meshpkg found as the URDF's ancestor directory
  const double q1 = 0.7;
  JointVector q(1);
  q << q1;
  const auto shapes = r.collision_shapes(q);
  REQUIRE(shapes.size() == 2);
  for (const PlacedShape& s : shapes) {
    REQUIRE(s.shape.kind == LinkShape::Kind::mesh);
    REQUIRE(s.shape.mesh != nullptr);
    CHECK(s.shape.mesh->closed());
    CHECK(s.shape.mesh->vertices().size() == 8);  // the STL's 36 corners welded
  }
  CHECK(shapes[0].shape.size == Vec3(2, 1, 1));
  CHECK(shapes[0].shape.mesh_path == "package://meshpkg/meshes/box.stl");
  // Scale applied in G: the base box is 0.2 × 0.06 × 0.04.
  CHECK((shapes[0].shape.mesh->bounds().extent() - Vec3(0.2, 0.06, 0.04)).norm() < 1e-7);  // float32 STL
  CHECK((shapes[1].shape.mesh->bounds().extent() - kBox).norm() < 1e-15);                  // ASCII: exact
  CHECK(r.collision_shapes(JointVector::Zero(1))[1].shape.mesh == shapes[1].shape.mesh);   // loaded once, shared
  // fk placement by hand: arm frame = Rz(q1) at (0, 0, 0.1); the mesh frame (0.2, 0, 0), Rz(0.3) in it.
  const Mat3 R = Eigen::AngleAxisd(q1 + 0.3, Vec3::UnitZ()).toRotationMatrix();
  const Vec3 centre = Vec3(0, 0, 0.1) + Eigen::AngleAxisd(q1, Vec3::UnitZ()).toRotationMatrix() * Vec3(0.2, 0, 0);
  CHECK((shapes[1].T_WG.translation() - centre).norm() < 1e-12);
  CHECK((shapes[1].T_WG.linear() - R).norm() < 1e-12);
  CHECK((shapes[0].T_WG.translation() - Vec3(0, 0, 0.05)).norm() < 1e-12);
  LinkShape prim;
  prim.size = kBox;
  const Aabb want = detail::shape_bounds(prim, shapes[1].T_WG);
  const Aabb got = detail::shape_bounds(shapes[1].shape, shapes[1].T_WG);
  CHECK((want.min - got.min).norm() < 1e-12);
  CHECK((want.max - got.max).norm() < 1e-12);
}

TEST_CASE("UrdfRobot: package:// search rule (given roots, ROS_PACKAGE_PATH) and file:// paths", "[kdl][mesh]") {
  const Package pkg;
  // The same URDF outside its package: not found, unless a root or ROS_PACKAGE_PATH names the workspace.
  const fs::path elsewhere =
      fs::temp_directory_path() / ("nbs_test_kdl_mesh_elsewhere_" + std::to_string(::getpid()) + ".urdf");
  std::string text;
  {
    std::ifstream in(pkg.urdf);
    text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  const std::string rel = "../meshes/box_ascii.stl";
  const std::string abs = "file://" + (pkg.ws / "meshpkg/meshes/box_ascii.stl").string();
  text.replace(text.find(rel), rel.size(), abs);
  std::ofstream(elsewhere) << text;
  const EnvRestore restore("ROS_PACKAGE_PATH");  // the process's value comes back at the end of the test
  ::unsetenv("ROS_PACKAGE_PATH");
  CHECK_THROWS_AS(load(elsewhere), FileError);
  CHECK_THROWS_WITH(load(elsewhere), Contains(elsewhere.string()) && Contains("link 'base'") &&
                                         Contains("package://meshpkg/meshes/box.stl") && Contains("not found"));
  CHECK(load(elsewhere, {fs::path("/nonexistent"), pkg.ws}).collision_shapes(JointVector::Zero(1)).size() == 2);
  CHECK(load(elsewhere, {pkg.ws / "meshpkg"}).collision_shapes(JointVector::Zero(1)).size() == 2);  // root = package
  ::setenv("ROS_PACKAGE_PATH", ("/nonexistent::" + pkg.ws.string()).c_str(), 1);
  CHECK(load(elsewhere).collision_shapes(JointVector::Zero(1))[0].shape.mesh != nullptr);
  fs::remove(elsewhere);
}

TEST_CASE("UrdfRobot: a missing, malformed or badly scaled mesh gives an error naming the link and the file",
          "[kdl][mesh][bad-input]") {
  {
    const Package pkg("package://meshpkg/meshes/box.stl", "../meshes/nothere.stl");
    CHECK_THROWS_AS(load(pkg.urdf), FileError);
    CHECK_THROWS_WITH(load(pkg.urdf), Contains("link 'arm'") && Contains("nothere.stl") && Contains("not found"));
  }
  {
    const Package pkg("package://meshpkg/meshes/bad.stl");
    std::ofstream(pkg.ws / "meshpkg" / "meshes" / "bad.stl") << "solid x\nfacet normal 0 0 1\nouter loop\n";
    CHECK_THROWS_AS(load(pkg.urdf), FileError);
    CHECK_THROWS_WITH(load(pkg.urdf), Contains(pkg.urdf.string()) && Contains("link 'base'") &&
                                          Contains("bad.stl") && Contains("endsolid"));
  }
  {
    const Package pkg("http://example.com/box.stl");
    CHECK_THROWS_WITH(load(pkg.urdf), Contains("link 'base'") && Contains("unsupported scheme"));
  }
  {
    const Package pkg("package://meshpkg/meshes/box.stl", "", R"(<mesh filename="../meshes/box.stl" scale="1 0 1"/>)");
    CHECK_THROWS_WITH(load(pkg.urdf), Contains("link 'arm'") && Contains("scale"));
  }
}

TEST_CASE("LinkCollisionChecker on a URDF mesh link: the same contacts as the link written as a <box>",
          "[kdl][mesh][collision]") {
  const Package meshed;
  const UrdfRobot a = load(meshed.urdf);
  const Package boxed("package://meshpkg/meshes/box.stl", "", R"(<box size="0.1 0.06 0.04"/>)");
  const UrdfRobot b = load(boxed.urdf);
  // One occupied 1 cm voxel column at x = 0.2 .. 0.21, y = 0 .. 0.01, z ∈ [0.08, 0.12): the arm sweeps through it.
  ProbabilisticVoxelSpace<> space(0.01, Aabb{Vec3(-0.3, -0.3, 0.0), Vec3(0.2999, 0.2999, 0.1999)});
  ThesisState occupied;
  occupied.surf = 6000;
  for (int z = 8; z < 12; ++z) set_voxel_state(space.mutable_backend(), VoxelKey{20, 0, z}, occupied);
  LinkCollisionSetting s;
  s.unknown_is_obstacle = false;
  s.table_exempt_links = {"base"};
  const LinkCollisionChecker ca(a, space, s), cb(b, space, s);
  int hits = 0;
  for (int i = 0; i <= 60; ++i) {
    JointVector q(1);
    q << -1.5 + 3.0 * i / 60;
    const auto x = ca.first_contact(q), y = cb.first_contact(q);
    INFO("q " << q[0]);
    REQUIRE(x.has_value() == y.has_value());
    if (!x) continue;
    ++hits;
    CHECK(x->link == "arm");
    CHECK(x->voxel == y->voxel);
  }
  CHECK(hits >= 3);
  CHECK(hits <= 30);
}

TEST_CASE("EnvRestore (the tests' guard): a variable's value, or its absence, comes back", "[kdl][mesh]") {
  const EnvRestore outer("NBS_TEST_ENV_RESTORE");  // leaves the process as it found it
  ::setenv("NBS_TEST_ENV_RESTORE", "a", 1);
  {
    const EnvRestore guard("NBS_TEST_ENV_RESTORE");
    ::unsetenv("NBS_TEST_ENV_RESTORE");
  }
  REQUIRE(std::getenv("NBS_TEST_ENV_RESTORE") != nullptr);
  CHECK(std::string(std::getenv("NBS_TEST_ENV_RESTORE")) == "a");
  ::unsetenv("NBS_TEST_ENV_RESTORE");
  {
    const EnvRestore guard("NBS_TEST_ENV_RESTORE");
    ::setenv("NBS_TEST_ENV_RESTORE", "b", 1);
  }
  CHECK(std::getenv("NBS_TEST_ENV_RESTORE") == nullptr);
}
