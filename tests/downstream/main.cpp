// SPDX-License-Identifier: BSD-3-Clause
// Uses the installed headers and every adapter it was configured with: fails to compile, link or run (exit 1) if
// the package is broken. Each adapter's check has a known answer.
#include <cmath>
#include <cstdio>

#ifdef NBS_DOWNSTREAM_PKGCONFIG
// The pkg-config build (scripts/test-package.sh) checks the flags pkg-config gives: the core check's headers and one
// header of each library nbs.pc requires (nanoflann, tinyobjloader, nlohmann_json). The umbrella takes GCC 135 s at
// -O1; the CMake build compiles it.
#include "nbs/core.hpp"
#include "nbs/io/read_obj.hpp"
#include "nbs/io/write_json.hpp"
#include "nbs/sim/detail/point_kd_tree.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"
#else
#include "nbs/nbs.hpp"  // the umbrella header: every core folder
#endif
#ifdef NBS_DOWNSTREAM_HAS_EMBREE
#include "nbs/embree/scene.hpp"
#endif
#ifdef NBS_DOWNSTREAM_HAS_OCTOMAP
#include "nbs/octomap/obstacle_model.hpp"
#endif
#ifdef NBS_DOWNSTREAM_HAS_FCL
#include "nbs/fcl/collision_checker.hpp"
#endif
#ifdef NBS_DOWNSTREAM_HAS_OMPL
#include <ompl/util/Console.h>

#include "nbs/ompl/transfer_planner.hpp"
#endif
#ifdef NBS_DOWNSTREAM_HAS_PNG
#include <png.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "nbs/png/write_png.hpp"
#endif
#ifdef NBS_DOWNSTREAM_HAS_KDL
#include <filesystem>
#include <fstream>

#include "nbs/kdl/urdf_robot.hpp"
#endif

namespace {
int failures = 0;
void check(bool ok, const char* what) {
  std::printf("nbs downstream %s: %s\n", what, ok ? "OK" : "FAILED");
  failures += ok ? 0 : 1;
}
[[maybe_unused]] nbs::Pose at(double x, double y, double z) {
  nbs::Pose p = nbs::Pose::Identity();
  p.translation() = nbs::Vec3(x, y, z);
  return p;
}
}  // namespace

int main() {
  nbs::Parameters p;
  p.validate();
  const auto v = nbs::Viewpoint::look_at(nbs::Vec3(0.3, 0, 0.1), nbs::Vec3::Zero());
  check(std::abs(v.view_direction().x() + 0.9487) < 1e-3, "core (view direction of a look-at viewpoint)");
  // The unknown area of a fresh space: every voxel has p = 0.5 > 0.05, so all of it is an obstacle.
  [[maybe_unused]] const nbs::ProbabilisticVoxelSpace<> space(0.01, nbs::Aabb{nbs::Vec3(-0.05, -0.05, 0.0),
                                                                               nbs::Vec3(0.05, 0.05, 0.1)});
#ifdef NBS_DOWNSTREAM_HAS_EMBREE
  nbs::IndexedMesh plane;
  plane.vertices = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  plane.triangles = {{0, 1, 2}, {0, 2, 3}};
  const nbs::embree::Scene scene(plane);
  const auto hit = scene.first_hit({0.1, 0.2, 0.5}, -nbs::Vec3::UnitZ(), 1.0);
  check(hit && std::abs(hit->distance - 0.5) < 1e-6, "embree (a ray 0.5 m above a plane)");
#endif
#ifdef NBS_DOWNSTREAM_HAS_OCTOMAP
  const auto tree = nbs::octomap::to_obstacle_octree(space, 0.05, 1'000'000);
  check(tree->getNumLeafNodes() > 0 && tree->search(0.0, 0.0, 0.05) != nullptr,
        "octomap (the unknown box is an obstacle octree)");
#endif
#ifdef NBS_DOWNSTREAM_HAS_FCL
  nbs::CollisionSetting cs;
  cs.head.size_m = nbs::Vec3(0.02, 0.02, 0.02);
  const nbs::fcl::FclCollisionChecker fcl_checker(space, cs);
  check(fcl_checker.collides(at(0, 0, 0.05)) && !fcl_checker.collides(at(0, 0, 0.5)),
        "fcl (a head inside the unknown box collides, one 0.4 m above it does not)");
#endif
#ifdef NBS_DOWNSTREAM_HAS_OMPL
  ::ompl::msg::setLogLevel(::ompl::msg::LOG_WARN);
  struct Wall {  // x ∈ [−0.01, 0.01], z ≤ 0.3: the straight motion collides
    [[nodiscard]] bool collides(const nbs::Pose& T) const {
      return nbs::Aabb{nbs::Vec3(-0.01, -0.2, -1.0), nbs::Vec3(0.01, 0.2, 0.3)}.contains(T.translation());
    }
  };
  nbs::ompl::TransferSetting ts;
  ts.workspace = nbs::Aabb{nbs::Vec3(-0.4, -0.4, 0.0), nbs::Vec3(0.4, 0.4, 0.5)};
  const auto path = nbs::ompl::plan_transfer(at(-0.2, 0, 0.1), at(0.2, 0, 0.1), Wall{}, ts);
  check(path.solved && path.poses.size() >= 3, "ompl (RRT-Connect around a wall)");
#endif
#ifdef NBS_DOWNSTREAM_HAS_PNG
  {  // 3 x 2 RGBA written, then decoded by libpng itself
    const std::vector<std::uint8_t> px{255, 0,   0,  255, 0,  255, 0,  128, 0,  0,  255, 0,
                                       10,  20,  30, 40,  50, 60,  70, 80,  90, 100, 110, 120};
    const std::string path = (std::filesystem::temp_directory_path() / "nbs_downstream.png").string();
    nbs::png::write_png(path, 3, 2, px, nbs::png::PixelFormat::rgba);
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    std::vector<std::uint8_t> back;
    if (png_image_begin_read_from_file(&image, path.c_str())) {
      image.format = PNG_FORMAT_RGBA;
      back.resize(PNG_IMAGE_SIZE(image));
      if (!png_image_finish_read(&image, nullptr, back.data(), 0, nullptr)) back.clear();
    }
    std::filesystem::remove(path);
    check(image.width == 3 && image.height == 2 && back == px, "png (a 3 x 2 RGBA image decodes to its pixels)");
  }
#endif
#ifdef NBS_DOWNSTREAM_HAS_KDL
  {  // one revolute joint about z with a 0.5 m arm along x: at q = π/2 the sensor is at (0, 0.5, 0)
    const std::filesystem::path path = std::filesystem::temp_directory_path() / "nbs_downstream.urdf";
    std::ofstream(path) << R"(<robot name="r"><link name="b"/><link name="f"/>
      <joint name="j" type="revolute"><parent link="b"/><child link="f"/><origin xyz="0 0 0"/><axis xyz="0 0 1"/>
      <limit lower="-3" upper="3" effort="1" velocity="1"/></joint></robot>)";
    auto robot = nbs::kdl::UrdfRobot::load(path, "b", "f", "f");
    std::filesystem::remove(path);
    robot.set_hand_eye(at(0.5, 0, 0));
    nbs::JointVector q(1);
    q << 1.5707963267948966;
    check((robot.fk(q).translation() - nbs::Vec3(0, 0.5, 0)).norm() < 1e-12, "kdl (a one-joint URDF arm at 90 degrees)");
  }
#endif
  return failures == 0 ? 0 : 1;
}
