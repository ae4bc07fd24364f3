// SPDX-License-Identifier: BSD-3-Clause
// Pictures of the arm (issue 19 item 5): the collision shapes as triangles (robot/shape_mesh.hpp) against the
// analytic volume and area of the shape (the inscribed polytope's closed form for box and cylinder, the limit for
// sphere and capsule), and the sensor path along a transfer (robot/transfer.hpp sensor_path) against the planar
// arm's circle.
#include "nbs_catch.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <map>
#include <memory>
#include <numbers>
#include <utility>

#include "nbs/robot/collision_mesh.hpp"
#include "nbs/robot/shape_mesh.hpp"
#include "nbs/robot/transfer.hpp"
#include "planar_robot.hpp"

using namespace nbs;

namespace {

constexpr double kPi = std::numbers::pi;

/// Volume enclosed by a closed triangle mesh (divergence theorem: Σ a · (b × c) / 6); positive if outward.
double enclosed_volume(const IndexedMesh& m) {
  double v = 0.0;
  for (const auto& t : m.triangles) v += m.vertices[t[0]].dot(m.vertices[t[1]].cross(m.vertices[t[2]])) / 6.0;
  return v;
}

/// True if every directed edge occurs once and its reverse once: closed, consistently oriented.
bool closed_and_oriented(const IndexedMesh& m) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) ++edges[{t[k], t[(k + 1) % 3]}];
  for (const auto& [e, n] : edges)
    if (n != 1 || edges.count({e.second, e.first}) == 0 || edges.at({e.second, e.first}) != 1) return false;
  return true;
}

PlacedShape shape(LinkShape::Kind kind, double radius, double length, const Vec3& size = Vec3::Zero(),
                  const Pose& T = Pose::Identity()) {
  PlacedShape s;
  s.link = "link_x";
  s.shape.kind = kind;
  s.shape.radius = radius;
  s.shape.length = length;
  s.shape.size = size;
  s.T_WG = T;
  return s;
}

}  // namespace

TEST_CASE("shape_mesh: box and cylinder equal their inscribed polytopes exactly", "[robot][shape_mesh]") {
  using K = LinkShape::Kind;
  Pose T = Pose::Identity();
  T.linear() = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  T.translation() = Vec3(0.3, -0.2, 0.5);

  const Vec3 size(0.12, 0.06, 0.10);
  const IndexedMesh box = shapes_mesh({shape(K::box, 0, 0, size, T)});
  CHECK(box.vertices.size() == 8);
  CHECK(box.triangles.size() == 12);
  CHECK(closed_and_oriented(box));
  CHECK(enclosed_volume(box) == Approx(size.prod()).epsilon(1e-12));
  CHECK(box.area() == Approx(2 * (size.x() * size.y() + size.y() * size.z() + size.x() * size.z())).epsilon(1e-12));
  for (const Vec3& v : box.vertices)  // every corner at (±sx/2, ±sy/2, ±sz/2) in the shape frame
    CHECK(((T.inverse() * v).cwiseAbs() - 0.5 * size).cwiseAbs().maxCoeff() < 1e-12);

  const double r = 0.06, h = 0.2;
  for (int n : {3, 8, 24}) {
    const IndexedMesh cyl = shapes_mesh({shape(K::cylinder, r, h, Vec3::Zero(), T)}, n);
    CHECK(cyl.vertices.size() == std::size_t(2 * n + 2));
    CHECK(closed_and_oriented(cyl));
    const double polygon = 0.5 * n * r * r * std::sin(2 * kPi / n), perimeter = 2 * n * r * std::sin(kPi / n);
    CHECK(enclosed_volume(cyl) == Approx(polygon * h).epsilon(1e-12));
    CHECK(cyl.area() == Approx(2 * polygon + perimeter * h).epsilon(1e-12));
    for (const Vec3& v : cyl.vertices) {  // on the caps' planes, on the axis or the mantle
      const Vec3 g = T.inverse() * v;
      CHECK(std::abs(std::abs(g.z()) - 0.5 * h) < 1e-12);
      const double rho = g.head<2>().norm();
      CHECK((rho < 1e-12 || std::abs(rho - r) < 1e-12));
    }
  }
}

TEST_CASE("shape_mesh: sphere and capsule converge to the analytic volume from below", "[robot][shape_mesh]") {
  using K = LinkShape::Kind;
  const double r = 0.06, h = 0.2;
  const double sphere_v = 4.0 / 3.0 * kPi * r * r * r, capsule_v = kPi * r * r * h + sphere_v;
  double prev_sphere = 1.0, prev_capsule = 1.0;
  for (int n : {12, 24, 48}) {
    const IndexedMesh s = shapes_mesh({shape(K::sphere, r, 0)}, n), c = shapes_mesh({shape(K::capsule, r, h)}, n);
    CHECK(closed_and_oriented(s));
    CHECK(closed_and_oriented(c));
    for (const Vec3& v : s.vertices) CHECK(std::abs(v.norm() - r) < 1e-12);
    for (const Vec3& v : c.vertices) {  // distance r from the axis segment z ∈ [−h/2, h/2]
      const Vec3 on_axis(0, 0, std::clamp(v.z(), -0.5 * h, 0.5 * h));
      CHECK(std::abs((v - on_axis).norm() - r) < 1e-12);
    }
    CHECK(s.bounds().max.z() == Approx(r).epsilon(1e-12));
    CHECK(c.bounds().min.z() == Approx(-0.5 * h - r).epsilon(1e-12));
    const double es = 1.0 - enclosed_volume(s) / sphere_v, ec = 1.0 - enclosed_volume(c) / capsule_v;
    // inscribed: below the volume, the error O(1/n²) (≈ 4x smaller per doubling; 2π²/n² bounds the sphere's)
    CHECK(es > 0.0);
    CHECK(ec > 0.0);
    CHECK(es < 2 * kPi * kPi / (n * n));
    CHECK(es < prev_sphere / 3.0);
    CHECK(ec < prev_capsule / 3.0);
    prev_sphere = es, prev_capsule = ec;
  }
}

TEST_CASE("shape_mesh: bad dimensions throw naming the link and append nothing; meshes drawn once loaded",
          "[robot][shape_mesh][bad-input]") {
  using K = LinkShape::Kind;
  IndexedMesh m = shapes_mesh({shape(K::sphere, 0.05, 0)});
  const IndexedMesh before = m;
  for (const PlacedShape& bad : {shape(K::sphere, -0.05, 0), shape(K::cylinder, 0.05, 0.0),
                                 shape(K::capsule, 0.05, std::nan("")), shape(K::box, 0, 0, Vec3(0.1, 0.0, 0.1))}) {
    CHECK_THROWS_WITH(append_shape_mesh(m, bad), nbs_test::Contains("link_x"));
    CHECK(m.vertices == before.vertices);
    CHECK(m.triangles == before.triangles);
  }
  CHECK_THROWS_AS(append_shape_mesh(m, shape(K::sphere, 0.05, 0), 2), InvalidArgument);
  PlacedShape file = shape(K::mesh, 0, 0, Vec3::Ones());
  file.shape.mesh_path = "package://arm/link.stl";
  append_shape_mesh(m, file);
  CHECK(m.triangles == before.triangles);  // not loaded: nothing to draw
  // Loaded: its triangles placed at T_WG (a 0.1 x 0.2 x 0.3 box mesh keeps its volume, its centre moves to T's).
  const Pose T = Eigen::Translation3d(0.4, -0.1, 0.2) * Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized());
  file.shape.mesh = std::make_shared<const CollisionMesh>(shapes_mesh({shape(K::box, 0, 0, Vec3(0.1, 0.2, 0.3))}));
  file.T_WG = T;
  IndexedMesh loaded;
  append_shape_mesh(loaded, file);
  REQUIRE(loaded.triangles.size() == 12);
  CHECK(enclosed_volume(loaded) == Approx(0.1 * 0.2 * 0.3).epsilon(1e-9));
  Vec3 centre = Vec3::Zero();
  for (const Vec3& v : loaded.vertices) centre += v / static_cast<double>(loaded.vertices.size());
  CHECK((centre - T.translation()).norm() < 1e-12);
  // The planar arm's three capsule links: three closed meshes, volumes add up.
  const test::PlanarArm arm;
  const IndexedMesh links = shapes_mesh(arm.collision_shapes(JointVector::Constant(3, 0.4)), 24);
  double expected = 0.0;
  for (double l : arm.l) expected += enclosed_volume(shapes_mesh({shape(K::capsule, 0.02, l)}, 24));
  CHECK(closed_and_oriented(links));
  CHECK(enclosed_volume(links) == Approx(expected).epsilon(1e-9));
}

TEST_CASE("sensor_path: dense fk along a transfer, against the planar arm's circles", "[robot][shape_mesh]") {
  const test::PlanarArm arm;
  const double reach = arm.l[0] + arm.l[1] + arm.l[2];
  JointVector q0 = JointVector::Zero(3), q1 = q0, q2 = q0;
  q1[0] = 0.5;             // joint 1 turns: the sensor on the circle of radius l1 + l2 + l3 about the base
  q2 = q1, q2[2] = -0.25;  // then joint 3: the circle of radius l3 about joint 3
  const std::vector<Vec3> p = sensor_path(arm, {q0, q1, q2}, 0.03);
  REQUIRE(p.size() == 1 + 17 + 9);  // ceil(0.5 / 0.03) + ceil(0.25 / 0.03) steps
  CHECK((p.front() - arm.fk(q0).translation()).norm() == 0.0);
  CHECK((p[17] - arm.fk(q1).translation()).norm() == 0.0);
  CHECK((p.back() - arm.fk(q2).translation()).norm() == 0.0);
  double first = 0.0, second = 0.0;
  for (std::size_t i = 1; i <= 17; ++i) {
    CHECK(std::abs(p[i].norm() - reach) < 1e-12);
    first += (p[i] - p[i - 1]).norm();
  }
  const Vec3 joint3 = arm.l[0] * test::PlanarArm::dir(0.5) + arm.l[1] * test::PlanarArm::dir(0.5);
  for (std::size_t i = 18; i < p.size(); ++i) {
    CHECK(std::abs((p[i] - joint3).norm() - arm.l[2]) < 1e-12);
    second += (p[i] - p[i - 1]).norm();
  }
  CHECK(first == Approx(17 * 2 * reach * std::sin(0.5 / 34)).epsilon(1e-12));  // chords of the arc
  CHECK(second == Approx(9 * 2 * arm.l[2] * std::sin(0.25 / 18)).epsilon(1e-12));
  CHECK(sensor_path(arm, {}, 0.02).empty());
  CHECK(sensor_path(arm, {q1}, 0.02).size() == 1);
  CHECK_THROWS_AS(sensor_path(arm, {q0, q1}, 0.0), InvalidArgument);
  CHECK_THROWS_AS(sensor_path(arm, {q0, q1}, std::nan("")), InvalidArgument);
  CHECK_THROWS_WITH(sensor_path(arm, {q0, JointVector::Zero(2)}),
                    nbs_test::Contains("sensor_path: waypoint 1 has 2 entries, the robot has 3 joints"));
  JointVector bad = q1;
  bad[1] = std::nan("");
  CHECK_THROWS_WITH(sensor_path(arm, {q0, q1, bad}), nbs_test::Contains("sensor_path: waypoint 2"));
  // 0.5 rad at 1e-9 rad per step: 5e8 points, more than the bound (no int overflow, no allocation).
  CHECK_THROWS_WITH(sensor_path(arm, {q0, q1}, 1e-9),
                    nbs_test::Contains("gives more than 10000000 points (500000000 from waypoint 0 to 1)"));
}
