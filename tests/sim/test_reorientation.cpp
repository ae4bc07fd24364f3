// SPDX-License-Identifier: BSD-3-Clause
// Stable placements for the second session (Sec. 5.3): a box lies stably on each of its six faces, a leaning prism
// and a turned-over L shape tip over, a cylinder lies on its side (both rules); a regular tetrahedron rests on its
// four facets, a hull facet beyond which the centre of mass lies is unstable (hull rule).

#include "nbs_catch.hpp"

#include <cmath>
#include <numbers>
#include <string>

#include "nbs/sim/reorientation.hpp"
#include "test_meshes.hpp"

using namespace nbs;

namespace {

/// Closed prism of the bottom quad (z = 0) and the top quad (z = h) shifted by `lean` in x: 6 quads.
IndexedMesh leaning_prism(double w, double h, double lean) {
  IndexedMesh m;
  const auto p = [&](int x, int y, int z) { return Vec3(x * w + z * lean, y * w, z * h); };
  test::add_quad(m, p(0, 0, 0), p(0, 1, 0), p(1, 1, 0), p(1, 0, 0));
  test::add_quad(m, p(0, 0, 1), p(1, 0, 1), p(1, 1, 1), p(0, 1, 1));
  test::add_quad(m, p(0, 0, 0), p(1, 0, 0), p(1, 0, 1), p(0, 0, 1));
  test::add_quad(m, p(0, 1, 0), p(0, 1, 1), p(1, 1, 1), p(1, 1, 0));
  test::add_quad(m, p(0, 0, 0), p(0, 0, 1), p(0, 1, 1), p(0, 1, 0));
  test::add_quad(m, p(1, 0, 0), p(1, 1, 0), p(1, 1, 1), p(1, 0, 1));
  return m;
}

/// Cylinder of radius r and height h about the z axis standing on z = 0, n segments, with both caps (fans).
IndexedMesh cylinder(double r, double h, int n) {
  IndexedMesh m;
  for (int z = 0; z < 2; ++z) {
    for (int k = 0; k < n; ++k) {
      const double a = 2.0 * std::numbers::pi * k / n;
      m.vertices.emplace_back(r * std::cos(a), r * std::sin(a), z * h);
    }
  }
  m.vertices.emplace_back(0, 0, 0);
  m.vertices.emplace_back(0, 0, h);
  const auto u = static_cast<std::uint32_t>(n);
  for (std::uint32_t k = 0; k < u; ++k) {
    const std::uint32_t k1 = (k + 1) % u;
    m.triangles.push_back({k, k1, k1 + u});
    m.triangles.push_back({k, k1 + u, k + u});
    m.triangles.push_back({2 * u, k1, k});
    m.triangles.push_back({2 * u + 1, k + u, k1 + u});
  }
  return m;
}

}  // namespace

TEST_CASE("a box lies stably on each of its six faces, the turn puts it on z = 0", "[sim][reorientation]") {
  const IndexedMesh box = test::box_mesh({-0.05, -0.03, 0.0}, {0.05, 0.03, 0.04});
  const std::vector<Placement> all = stable_placements(box);
  REQUIRE(all.size() == 6);
  for (const Placement& p : all) {
    INFO(to_string(p.face));
    CHECK((p.T_turn.linear() * p.down - Vec3(0, 0, -1)).norm() < 1e-12);
    CHECK(std::abs(p.T_turn.linear().determinant() - 1.0) < 1e-12);
    const IndexedMesh turned = transformed_mesh(box, p.T_turn);
    CHECK(turned.bounds().min.z() == Approx(0.0).margin(1e-12));
    const Vec3 c0 = surface_centroid(box), c1 = surface_centroid(turned);
    CHECK(c1.x() == Approx(c0.x()).margin(1e-12));
    CHECK(c1.y() == Approx(c0.y()).margin(1e-12));
    CHECK(p.margin_m > 0.0);
  }
  // Support areas: the ±z faces 0.1 × 0.06, the ±y faces 0.1 × 0.04, the ±x faces 0.06 × 0.04.
  CHECK(all[0].support_area_m2 == Approx(0.006));
  CHECK(all[2].support_area_m2 == Approx(0.004));
  CHECK(all[5].support_area_m2 == Approx(0.0024));
  CHECK(evaluate_placement(box, SupportFace::plus_x).margin_m == Approx(0.02));  // half the 0.04 m height
  // The turn for the second session: the largest stable face other than the one it stands on: upside down.
  const Placement turn = reorientation_placement(box);
  CHECK(turn.face == SupportFace::plus_z);
  const IndexedMesh flipped = transformed_mesh(box, turn.T_turn);
  CHECK(flipped.bounds().max.z() == Approx(0.04));
  CHECK(evaluate_placement(box, SupportFace::minus_z).T_turn.isApprox(Pose::Identity(), 1e-12));
}

TEST_CASE("a cylinder lies on its side; a leaning prism and an upside-down L tip over", "[sim][reorientation]") {
  SECTION("cylinder") {
    const IndexedMesh cyl = cylinder(0.04, 0.1, 24);
    // On its side the contact is the two generatrices within 2 mm: 2 r sin 15° wide, 0.1 m long.
    const Placement side = placement_on(cyl, SupportFace::plus_x);
    CHECK(side.support_area_m2 == Approx(0.1 * 2 * 0.04 * std::sin(std::numbers::pi / 12)));
    CHECK(side.margin_m == Approx(0.04 * std::sin(std::numbers::pi / 12)));
    // Without the tolerance the contact is a line: not stable.
    CHECK_FALSE(evaluate_placement(cyl, SupportFace::plus_x, {.contact_tolerance_m = 0.0}).stable);
    CHECK(reorientation_placement(cyl).face == SupportFace::plus_z);  // the cap is the largest contact
  }
  SECTION("leaning prism") {
    // 2 cm base, 20 cm tall, top shifted 5 cm: the centre of mass (x ≈ 3.5 cm) is beyond the base (x ≤ 2 cm).
    const IndexedMesh prism = leaning_prism(0.02, 0.2, 0.05);
    const Placement upright = evaluate_placement(prism, SupportFace::minus_z);
    CHECK_FALSE(upright.stable);
    CHECK(upright.margin_m == Approx(-0.015).margin(1e-9));
    try {
      (void)placement_on(prism, SupportFace::minus_z);
      FAIL("an unstable placement was accepted");
    } catch (const InvalidArgument& e) {
      const std::string what = e.what();
      CHECK(what.find("minus_z") != std::string::npos);
      CHECK(what.find("not stable") != std::string::npos);
    }
    // The ±x faces touch only along an edge of the leaning prism.
    CHECK_FALSE(evaluate_placement(prism, SupportFace::plus_x).stable);
    CHECK(evaluate_placement(prism, SupportFace::plus_x).support_area_m2 == 0.0);
  }
  SECTION("L shape") {
    // A long base box with a block on one end: upside down it would stand on the block's top only.
    IndexedMesh l = test::box_mesh({-0.04, -0.025, 0.0}, {0.04, 0.025, 0.03});
    const IndexedMesh block = test::box_mesh({0.01, -0.025, 0.03}, {0.04, 0.025, 0.06});
    for (const auto& t : block.triangles)
      l.triangles.push_back({t[0] + 8u, t[1] + 8u, t[2] + 8u});
    l.vertices.insert(l.vertices.end(), block.vertices.begin(), block.vertices.end());
    CHECK_FALSE(evaluate_placement(l, SupportFace::plus_z).stable);
    const Placement turn = reorientation_placement(l);
    CHECK(turn.face == SupportFace::minus_y);  // the L-shaped side (hull 0.08 × 0.06 minus a corner)
    CHECK(turn.support_area_m2 == Approx(0.08 * 0.06 - 0.5 * 0.03 * 0.05));
  }
  SECTION("bad input") {
    const IndexedMesh box = test::box_mesh({0, 0, 0}, {0.1, 0.1, 0.1});
    CHECK_THROWS_AS(evaluate_placement(box, SupportFace::plus_x, {.contact_tolerance_m = -1.0}), InvalidArgument);
    CHECK_THROWS_AS(evaluate_placement(IndexedMesh{}, SupportFace::plus_x), InvalidArgument);
    // A sphere touches the box's faces in one vertex whichever way it is turned (bounding-box rule); on its hull it
    // rests on a facet (the polygonal sphere's facets are planar quads around the foot of the centre).
    const IndexedMesh sphere = test::uv_sphere({0, 0, 0.05}, 0.05, 8, 16);
    CHECK_THROWS_AS(reorientation_placement(sphere, {.rule = PlacementRule::bounding_box}), InvalidArgument);
    const Placement on_facet = reorientation_placement(sphere);
    CHECK(on_facet.hull_facet >= 0);
    CHECK(on_facet.support_area_m2 > 0.0);
    CHECK(on_facet.margin_m > 0.0);
    CHECK_THROWS_AS(reorientation_placement(box, {.min_turn_rad = -0.1}), InvalidArgument);
  }
}

TEST_CASE("hull rule: the box's and the L shape's turns equal the bounding-box rule's", "[sim][reorientation]") {
  const IndexedMesh box = test::box_mesh({-0.05, -0.03, 0.0}, {0.05, 0.03, 0.04});
  const std::vector<Placement> hull = stable_placements(box);
  const std::vector<Placement> bbox = stable_placements(box, {.rule = PlacementRule::bounding_box});
  REQUIRE(hull.size() == 6);
  REQUIRE(bbox.size() == 6);
  for (std::size_t i = 0; i < 6; ++i) {
    INFO(to_string(bbox[i].face));
    CHECK(hull[i].face == bbox[i].face);
    CHECK(hull[i].hull_facet >= 0);
    CHECK(bbox[i].hull_facet == -1);
    CHECK(hull[i].support_area_m2 == Approx(bbox[i].support_area_m2));
    CHECK(hull[i].margin_m == Approx(bbox[i].margin_m));
    CHECK(hull[i].T_turn.isApprox(bbox[i].T_turn, 1e-12));
  }
  CHECK(reorientation_placement(box).face == SupportFace::plus_z);
  // The L block (two boxes, not closed by index: the surface centroid under both rules) turns the same way.
  IndexedMesh l = test::box_mesh({-0.04, -0.025, 0.0}, {0.04, 0.025, 0.03});
  const IndexedMesh block = test::box_mesh({0.01, -0.025, 0.03}, {0.04, 0.025, 0.06});
  for (const auto& t : block.triangles) l.triangles.push_back({t[0] + 8u, t[1] + 8u, t[2] + 8u});
  l.vertices.insert(l.vertices.end(), block.vertices.begin(), block.vertices.end());
  const Placement lh = reorientation_placement(l);
  const Placement lb = reorientation_placement(l, {.rule = PlacementRule::bounding_box});
  CHECK(lh.face == SupportFace::minus_y);
  CHECK(lb.face == SupportFace::minus_y);
  CHECK(lh.T_turn.isApprox(lb.T_turn, 1e-12));
  CHECK(lh.support_area_m2 == Approx(lb.support_area_m2));
}

TEST_CASE("hull rule: a regular tetrahedron rests on its four facets", "[sim][reorientation]") {
  IndexedMesh t;
  const double s = 0.05;
  t.vertices = {s * Vec3(1, 1, 1), s * Vec3(1, -1, -1), s * Vec3(-1, 1, -1), s * Vec3(-1, -1, 1)};
  t.triangles = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};  // outward, closed
  for (auto& v : t.vertices) v.z() += s;
  CHECK(centre_of_mass(t).isApprox(Vec3(0, 0, s), 1e-12));
  const std::vector<Placement> all = stable_placements(t);
  REQUIRE(all.size() == 4);
  const double edge = 2 * std::sqrt(2.0) * s;
  for (const Placement& p : all) {
    CHECK(p.support_area_m2 == Approx(std::sqrt(3.0) / 4 * edge * edge));
    CHECK(p.margin_m == Approx(edge / (2 * std::sqrt(3.0))));  // the inradius: the centroid projects to the centre
    const IndexedMesh turned = transformed_mesh(t, p.T_turn);
    int on_table = 0;
    for (const Vec3& v : turned.vertices) on_table += std::abs(v.z()) < 1e-12 ? 1 : 0;
    CHECK(on_table == 3);
    CHECK(turned.bounds().min.z() == Approx(0.0).margin(1e-12));
    CHECK(std::abs(p.T_turn.linear().determinant() - 1.0) < 1e-12);
  }
}

TEST_CASE("hull rule: the leaning prism tips over its base and lies on a slanted side", "[sim][reorientation]") {
  const IndexedMesh prism = leaning_prism(0.02, 0.2, 0.05);
  const std::vector<Placement> all = hull_placements(prism);
  REQUIRE(all.size() == 6);  // a parallelepiped
  int flat = 0;
  for (const Placement& p : all) {
    if (std::abs(p.down.z()) < 0.999) continue;
    ++flat;  // base and top: the centre of mass (x = 3.5 cm) is 1.5 cm beyond the 2 cm base
    CHECK_FALSE(p.stable);
    CHECK(p.margin_m == Approx(-0.015).margin(1e-9));
  }
  CHECK(flat == 2);
  const Placement turn = reorientation_placement(prism);
  CHECK(turn.face == SupportFace::minus_x);  // the slanted sides (0.02 × 0.206 m) are larger than the ±y ones
  CHECK(turn.support_area_m2 == Approx(0.02 * std::hypot(0.2, 0.05)));
  CHECK(turn.margin_m > 0.0);
  CHECK(transformed_mesh(prism, turn.T_turn).bounds().min.z() == Approx(0.0).margin(1e-12));
  SECTION("flat mesh has no hull") {
    IndexedMesh flat_mesh;
    test::add_quad(flat_mesh, {0, 0, 0}, {0.1, 0, 0}, {0.1, 0.1, 0}, {0, 0.1, 0});
    CHECK_THROWS_WITH(hull_placements(flat_mesh), Catch::Contains("coplanar"));
  }
}

TEST_CASE("hull rule: a top facet tilted 2 urad from +z still gives a rigid turn", "[sim][reorientation]") {
  // Eigen's FromTwoVectors(d, −z) for d within a few µrad of +z returns a quaternion off unit length by ≈ 1e-5.
  IndexedMesh box = test::box_mesh(Vec3(-0.04, -0.03, 0.0), Vec3(0.04, 0.03, 0.05));
  for (Vec3& v : box.vertices)
    if (v.z() > 0.0) v.z() += 2e-6 * v.x();  // the top tilted by 2 µrad about y
  bool near_up = false;
  for (const Placement& p : hull_placements(box)) {
    INFO("down " << p.down.transpose());
    const Mat3 R = p.T_turn.linear();
    CHECK((R.transpose() * R - Mat3::Identity()).norm() < 1e-12);
    CHECK((R * p.down + Vec3::UnitZ()).norm() < 1e-12);
    CHECK_NOTHROW(validate_pose(p.T_turn, "turn"));
    near_up = near_up || (p.down.z() > 0.999999 && p.down.z() < 1.0);
  }
  CHECK(near_up);
}
