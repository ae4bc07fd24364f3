// SPDX-License-Identifier: BSD-3-Clause
// Replanning for occlusions and collisions (Sec. 4.5.2, Alg. 3, Eq. 4.29) and the core collision checker.
// Oracles: Eigen::AngleAxis for Eq. 4.29, analytic segment/box geometry for visibility, corner-projection SAT for
// collisions (tests/fcl/box_oracle.hpp), brute force over the 81 rotations for the choice of Alg. 3.
#include "nbs_catch.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "nbs/space/probabilistic_voxel_space.hpp"
#include "../fcl/box_oracle.hpp"
#include "nbs/candidates/replanning.hpp"
#include "nbs_random.hpp"

namespace {
using nbs::Aabb;
using nbs::Mat3;
using nbs::Pose;
using nbs::Vec3;
using Space = nbs::ProbabilisticVoxelSpace<>;
constexpr double kDeg = std::numbers::pi / 180.0;

// A space of edge l over `bounds` whose voxels overlapping `boxes` are occupied: one scan, one beam from `from` to
// each such voxel centre. `prob_free` of the thesis model sets p of the voxels the beams pass.
Space space_with(double l, const Aabb& bounds, const std::vector<Aabb>& boxes, const Vec3& from,
                 double prob_free = 0.4) {
  nbs::ThesisModel::Setting ms;
  ms.prob_free = prob_free;
  Space space(l, bounds, nbs::ThesisModel(ms));
  nbs::Scan scan;
  Pose p = Pose::Identity();
  p.translation() = from;
  scan.profile_poses.push_back(p);
  for (const Aabb& b : boxes) {
    const nbs::KeyBox kb = space.grid().key_box(Aabb{b.min, b.max - Vec3::Constant(1e-9)});
    for (int z = kb.min.z; z <= kb.max.z; ++z)
      for (int y = kb.min.y; y <= kb.max.y; ++y)
        for (int x = kb.min.x; x <= kb.max.x; ++x) scan.add_point(space.grid().center({x, y, z}), 0);
  }
  (void)space.integrate(scan);
  return space;
}

// Slab test: does the segment a→b meet the box?
bool segment_hits(const Vec3& a, const Vec3& b, const Aabb& box) {
  double t0 = 0.0, t1 = 1.0;
  for (int i = 0; i < 3; ++i) {
    const double d = b[i] - a[i];
    if (std::abs(d) < 1e-15) {
      if (a[i] < box.min[i] || a[i] > box.max[i]) return false;
      continue;
    }
    double lo = (box.min[i] - a[i]) / d, hi = (box.max[i] - a[i]) / d;
    if (lo > hi) std::swap(lo, hi);
    t0 = std::max(t0, lo);
    t1 = std::min(t1, hi);
    if (t0 > t1) return false;
  }
  return true;
}

Aabb grown(const Aabb& b, double m) { return {b.min.array() - m, b.max.array() + m}; }

// The scene of the main test: line sensor looking along −x at a row of 10 targets on the line x = 0, z = 0.05,
// d_s = 0.3 m, path along +y from y = −0.05 to 0.05; a wall of voxels at x ∈ [0.10, 0.12) hides the targets with
// y < 0.01 for the unrotated path (6 of 10 hidden).
struct WallScene {
  double l = 0.005;
  double d_s = 0.3;
  Aabb bounds{Vec3(-0.05, -0.12, -0.05), Vec3(0.15, 0.12, 0.15)};
  Aabb wall{Vec3(0.10, -0.12, 0.005), Vec3(0.12, 0.01, 0.095)};
  Vec3 aim = Vec3(0.0, 0.0, 0.05);
  nbs::SensorGeometry sensor{nbs::SensorGeometry::Kind::line, {0.15, 0.45}, 0.5, 0.0};
  std::vector<nbs::SurfaceTarget> targets;
  nbs::LinearScanPath path;
  Space space;

  WallScene() : space(space_with(l, bounds, {wall}, Vec3(0.5, -0.05, 0.05))) {
    for (int k = 0; k < 10; ++k) targets.push_back({Vec3(0.0, -0.0438 + 0.01 * k, 0.05), Vec3::UnitX()});
    const Vec3 s_z(-1, 0, 0), s_y(0, 1, 0), s_x = s_y.cross(s_z);
    path = nbs::LinearScanPath(nbs::Viewpoint::from_axes(s_x, s_y, s_z, Vec3(0.3, -0.05, 0.05)),
                               Vec3(0.3, 0.05, 0.05));
  }
};

// Analytic visibility of the wall scene for rotation (bx, by): each target is seen from t − d_s·s'_z (the path
// point that keeps it at d_s); the ray, without its last 2 voxels, must miss the wall. Returns the number of targets
// visible even with the wall grown by `margin` and the number hidden even with the wall shrunk by it.
std::pair<int, int> oracle_counts(const WallScene& sc, double bx, double by, double margin) {
  const Vec3 s_x = sc.path.start().x_axis(), s_y = sc.path.start().y_axis(), s_z = sc.path.start().view_direction();
  const Vec3 z = Eigen::AngleAxisd(by, s_y) * (Eigen::AngleAxisd(bx, s_x) * s_z);
  int visible = 0, hidden = 0;
  for (const auto& t : sc.targets) {
    const Vec3 sensor = t.point - sc.d_s * z;
    const Vec3 end = t.point + 2.0 * sc.l * (sensor - t.point).normalized();
    if (!segment_hits(sensor, end, grown(sc.wall, margin))) ++visible;
    if (segment_hits(sensor, end, grown(sc.wall, -margin))) ++hidden;
  }
  return {visible, hidden};
}

struct Rotation {
  double bx, by;
};
std::vector<Rotation> thesis_order() {
  std::vector<Rotation> out;
  for (double bx : {0, 10, -10, 20, -20, 30, -30, 40, -40})
    for (double by : {0, 10, -10, 20, -20, 30, -30, 40, -40}) out.push_back({bx * kDeg, by * kDeg});
  return out;
}

// Brute force over the 81 rotations with the library's building blocks: the first (thesis order) that passes.
template <class Checker>
std::optional<Rotation> brute_force(const WallScene& sc, const Checker& checker) {
  for (const Rotation& r : thesis_order()) {
    const auto p = nbs::rotate_scan_path(sc.path, sc.aim, r.bx, r.by);
    if (nbs::visible_fraction(sc.space, p, sc.targets, sc.sensor) >= 0.5 &&
        nbs::collision_free_fraction(checker, p, 0.01) >= 0.5)
      return r;
  }
  return std::nullopt;
}

}  // namespace

TEST_CASE("Eq. 4.29 equals Eigen::AngleAxis", "[replanning]") {
  std::mt19937_64 rng(29);
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> angle(-std::numbers::pi, std::numbers::pi);
  for (int i = 0; i < 200; ++i) {
    const Vec3 a = nbs_test::random_vec3(g, rng).normalized();
    const double beta = angle(rng);
    const Mat3 r = nbs::axis_rotation(a, beta);
    REQUIRE((r - Eigen::AngleAxisd(beta, a).toRotationMatrix()).cwiseAbs().maxCoeff() < 1e-12);
  }
  CHECK_THROWS_AS(nbs::axis_rotation(Vec3(1, 1, 0), 0.1), nbs::InvalidArgument);
  CHECK_THROWS_AS(nbs::axis_rotation(Vec3(1, 0, 0), std::nan("")), nbs::InvalidArgument);
}

TEST_CASE("Alg. 3 angle order: 0 first, then + and − of increasing magnitude", "[replanning]") {
  const auto a = nbs::alg3_angles(10 * kDeg, 4);
  const std::vector<double> thesis{0, 10, -10, 20, -20, 30, -30, 40, -40};
  REQUIRE(a.size() == thesis.size());
  for (std::size_t i = 0; i < a.size(); ++i) CHECK(a[i] == Approx(thesis[i] * kDeg).margin(1e-15));
}

TEST_CASE("rotate_scan_path keeps the aim at d_s, the axes orthonormal and the end surface points", "[replanning]") {
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  for (int trial = 0; trial < 20; ++trial) {
    const Pose start = nbs::test::random_pose(rng, Vec3::Constant(-0.5), Vec3::Constant(0.5));
    const nbs::Viewpoint v(start);
    const double d_s = 0.2 + 0.2 * (u(rng) + 0.2), length = 0.3 * (u(rng) + 0.2) / 0.4, at = (u(rng) + 0.2) / 0.4;
    const nbs::LinearScanPath path(v, v.position() + length * v.y_axis());
    const Vec3 aim = v.position() + at * length * v.y_axis() + d_s * v.view_direction();
    for (const auto& r : thesis_order()) {
      const auto p = nbs::rotate_scan_path(path, aim, r.bx, r.by);
      const Mat3 rot = p.start().pose().linear();
      REQUIRE((rot.transpose() * rot - Mat3::Identity()).cwiseAbs().maxCoeff() < 1e-12);
      REQUIRE(rot.determinant() == Approx(1.0).margin(1e-12));
      // The frame is the rigid rotation R(s_y, β_y)·R(s_x, β_x) of the original one.
      const Mat3 expected = Eigen::AngleAxisd(r.by, v.y_axis()) * Eigen::AngleAxisd(r.bx, v.x_axis()) *
                            start.linear();
      REQUIRE((rot - expected).cwiseAbs().maxCoeff() < 1e-12);
      // The aim is at d_s along s'_z from the point of the new path at the same parameter.
      const Vec3 foot = aim - d_s * p.start().view_direction();
      const Vec3 on_path = (1.0 - at) * p.start().position() + at * p.end_position();
      REQUIRE((foot - on_path).norm() < 1e-12);
      // The surface points of the path ends (Eq. 4.18) are kept.
      REQUIRE((p.start().position() + d_s * p.start().view_direction() - (v.position() + d_s * v.view_direction()))
                  .norm() < 1e-12);
      REQUIRE((p.end_position() + d_s * p.start().view_direction() -
               (path.end_position() + d_s * v.view_direction())).norm() < 1e-12);
    }
    const auto same = nbs::rotate_scan_path(path, aim, 0.0, 0.0);
    REQUIRE((same.start().pose().matrix() - start.matrix()).cwiseAbs().maxCoeff() < 1e-12);
  }
}

TEST_CASE("visible_fraction agrees with analytic ray/wall geometry for all 81 rotations", "[replanning]") {
  const WallScene sc;
  for (const auto& c : {Vec3(0.11, -0.05, 0.05), Vec3(0.11, 0.005, 0.01), Vec3(0.101, -0.119, 0.094)})
    REQUIRE(sc.space.occupied(*sc.space.grid().key_of(c)));
  const double n = static_cast<double>(sc.targets.size());
  int decided = 0;
  for (const auto& r : thesis_order()) {
    const auto [visible, hidden] = oracle_counts(sc, r.bx, r.by, 0.003);
    const double f = nbs::visible_fraction(sc.space, nbs::rotate_scan_path(sc.path, sc.aim, r.bx, r.by), sc.targets,
                                           sc.sensor);
    INFO("beta_x " << r.bx / kDeg << " beta_y " << r.by / kDeg);
    REQUIRE(f * n >= visible - 1e-9);
    REQUIRE(f * n <= n - hidden + 1e-9);
    decided += (visible + hidden == static_cast<int>(n)) ? 1 : 0;
  }
  CHECK(decided >= 60);  // the bounds above are tight for most rotations
}

TEST_CASE("Alg. 3 replans around a wall: the first rotation in thesis order that works", "[replanning]") {
  const WallScene sc;
  const auto [v0, h0] = oracle_counts(sc, 0.0, 0.0, 0.003);
  REQUIRE(v0 == 4);  // unrotated: occluded (4 of 10 visible)
  REQUIRE(h0 == 6);
  const auto expected = brute_force(sc, nbs::NoCollisions{});
  REQUIRE(expected);
  // The analytic oracle: every rotation before the answer hides more than half, the answer shows at least half.
  for (const auto& r : thesis_order()) {
    const auto [visible, hidden] = oracle_counts(sc, r.bx, r.by, 0.003);
    if (r.bx == expected->bx && r.by == expected->by) {
      REQUIRE(visible >= 5);
      break;
    }
    REQUIRE(hidden > 5);
  }
  nbs::LinearScanPath path = sc.path;
  const auto report = nbs::replan(path, sc.aim, sc.targets, sc.space, nbs::NoCollisions{}, sc.sensor);
  REQUIRE(report.outcome == nbs::ReplanOutcome::rotated);
  CHECK(report.beta_x_rad == expected->bx);
  CHECK(report.beta_y_rad == expected->by);
  CHECK(report.visible_fraction >= 0.5);
  CHECK(report.collision_free_fraction == 1.0);
  const auto want = nbs::rotate_scan_path(sc.path, sc.aim, expected->bx, expected->by);
  CHECK((path.start().pose().matrix() - want.start().pose().matrix()).cwiseAbs().maxCoeff() == 0.0);
  CHECK((path.end_position() - want.end_position()).norm() == 0.0);
  // β_x is the outer loop: a pure rotation about s_x (β_x = 10°) would also work but comes later.
  CHECK(oracle_counts(sc, 10 * kDeg, 0.0, 0.003).first >= 5);
  CHECK(report.beta_x_rad == 0.0);
  CHECK(report.rotations_tried > 1);
}

TEST_CASE("Alg. 3 with a support plane: sensor positions below it are never accepted", "[replanning]") {
  const WallScene sc;
  // The answer without a support plane, for comparison.
  const auto free_answer = brute_force(sc, nbs::NoCollisions{});
  REQUIRE(free_answer);
  for (const double plane_z : {0.04, 0.06, 0.10, 0.20}) {
    nbs::ReplanSetting rs;
    rs.support_plane_z_m = plane_z;
    // Brute force: the first rotation in thesis order with both path ends on or above the plane that passes.
    std::optional<Rotation> expected;
    bool any_above = false;
    for (const Rotation& r : thesis_order()) {
      const auto p = nbs::rotate_scan_path(sc.path, sc.aim, r.bx, r.by);
      if (p.start().position().z() < plane_z || p.end_position().z() < plane_z) continue;
      any_above = true;
      if (nbs::visible_fraction(sc.space, p, sc.targets, sc.sensor) >= 0.5) {
        expected = r;
        break;
      }
    }
    nbs::LinearScanPath path = sc.path;
    const auto report = nbs::replan(path, sc.aim, sc.targets, sc.space, nbs::NoCollisions{}, sc.sensor, rs);
    INFO("plane z " << plane_z);
    REQUIRE(report.accepted() == expected.has_value());
    if (expected) {
      CHECK(report.beta_x_rad == expected->bx);
      CHECK(report.beta_y_rad == expected->by);
      CHECK(path.start().position().z() >= plane_z);
      CHECK(path.end_position().z() >= plane_z);
    } else {
      CHECK(report.outcome == (any_above ? nbs::ReplanOutcome::dropped_occluded
                                         : nbs::ReplanOutcome::dropped_in_collision));
    }
  }
  // Below every rotation (0.05 − 0.3 sin 40° > −0.2) the plane changes nothing; above every one (< 0.25) all drop.
  nbs::ReplanSetting low, high;
  low.support_plane_z_m = -0.2;
  high.support_plane_z_m = 0.25;
  nbs::LinearScanPath a = sc.path, b = sc.path;
  const auto ra = nbs::replan(a, sc.aim, sc.targets, sc.space, nbs::NoCollisions{}, sc.sensor, low);
  CHECK(ra.beta_x_rad == free_answer->bx);
  CHECK(ra.beta_y_rad == free_answer->by);
  CHECK(nbs::replan(b, sc.aim, sc.targets, sc.space, nbs::NoCollisions{}, sc.sensor, high).outcome ==
        nbs::ReplanOutcome::dropped_in_collision);
  nbs::ReplanSetting bad;
  bad.support_plane_z_m = std::nan("");
  CHECK_THROWS_AS(bad.validate(), nbs::InvalidArgument);
  bad.support_plane_z_m = std::numeric_limits<double>::infinity();
  CHECK_THROWS_AS(bad.validate(), nbs::InvalidArgument);
}

TEST_CASE("Alg. 3 with collisions: a table below the scene moves the answer", "[replanning]") {
  const WallScene sc;
  nbs::CollisionSetting cs;
  cs.static_scene.push_back(Aabb{Vec3(-1, -1, -1), Vec3(1, 1, -0.05)});
  const nbs::VoxelCollisionChecker checker(sc.space, cs);
  const auto free_only = brute_force(sc, nbs::NoCollisions{});
  const auto expected = brute_force(sc, checker);
  REQUIRE(free_only);
  REQUIRE(expected);
  REQUIRE((expected->bx != free_only->bx || expected->by != free_only->by));
  // Oracle for the collision part of the answer: every 10 mm pose of the accepted path clears the table.
  const auto accepted = nbs::rotate_scan_path(sc.path, sc.aim, expected->bx, expected->by);
  const auto obstacles = nbs::test::obstacle_boxes(sc.space, cs);
  for (int k = 0; k <= 10; ++k) CHECK(nbs::test::oracle_collides(obstacles, cs.head, accepted.pose_at(k / 10.0), 0.001) == 0);
  const auto rejected = nbs::rotate_scan_path(sc.path, sc.aim, free_only->bx, free_only->by);
  CHECK(nbs::test::oracle_collides(obstacles, cs.head, rejected.pose_at(0.5), 0.001) == 1);

  nbs::LinearScanPath path = sc.path;
  const auto report = nbs::replan(path, sc.aim, sc.targets, sc.space, checker, sc.sensor);
  REQUIRE(report.outcome == nbs::ReplanOutcome::rotated);
  CHECK(report.beta_x_rad == expected->bx);
  CHECK(report.beta_y_rad == expected->by);
  CHECK(report.collision_checks >= 2);
}

TEST_CASE("Alg. 3 keeps a free candidate and drops enclosed ones", "[replanning]") {
  WallScene sc;
  SECTION("nothing in the way: unchanged after one rotation") {
    sc.space = space_with(sc.l, sc.bounds, {}, Vec3(0.5, 0, 0.05));
    nbs::LinearScanPath path = sc.path;
    const auto r = nbs::replan(path, sc.aim, sc.targets, sc.space, nbs::NoCollisions{}, sc.sensor);
    CHECK(r.outcome == nbs::ReplanOutcome::unchanged);
    CHECK(r.rotations_tried == 1);
    CHECK(r.visible_fraction == 1.0);
    CHECK((path.start().pose().matrix() - sc.path.start().pose().matrix()).cwiseAbs().maxCoeff() == 0.0);
  }
  SECTION("targets inside a closed shell of occupied voxels: dropped as occluded") {
    const Aabb in{Vec3(-0.03, -0.07, 0.02), Vec3(0.03, 0.07, 0.08)};
    const double t = sc.l;
    const std::vector<Aabb> shell{
        {Vec3(in.min.x() - t, in.min.y() - t, in.min.z() - t), Vec3(in.max.x() + t, in.max.y() + t, in.min.z())},
        {Vec3(in.min.x() - t, in.min.y() - t, in.max.z()), Vec3(in.max.x() + t, in.max.y() + t, in.max.z() + t)},
        {Vec3(in.min.x() - t, in.min.y() - t, in.min.z()), Vec3(in.min.x(), in.max.y() + t, in.max.z())},
        {Vec3(in.max.x(), in.min.y() - t, in.min.z()), Vec3(in.max.x() + t, in.max.y() + t, in.max.z())},
        {Vec3(in.min.x(), in.min.y() - t, in.min.z()), Vec3(in.max.x(), in.min.y(), in.max.z())},
        {Vec3(in.min.x(), in.max.y(), in.min.z()), Vec3(in.max.x(), in.max.y() + t, in.max.z())}};
    sc.space = space_with(sc.l, sc.bounds, shell, Vec3(0.0, 0.0, 0.05));  // beams from inside: shell stays closed
    nbs::LinearScanPath path = sc.path;
    const auto r = nbs::replan(path, sc.aim, sc.targets, sc.space, nbs::NoCollisions{}, sc.sensor);
    CHECK(r.outcome == nbs::ReplanOutcome::dropped_occluded);
    CHECK(r.rotations_tried == 81);
    CHECK(r.collision_checks == 0);
    CHECK(r.visible_fraction == 0.0);
    CHECK((path.start().pose().matrix() - sc.path.start().pose().matrix()).cwiseAbs().maxCoeff() == 0.0);
  }
  SECTION("every pose inside a static box: dropped as in collision") {
    sc.space = space_with(sc.l, sc.bounds, {}, Vec3(0.5, 0, 0.05));
    nbs::CollisionSetting cs;
    cs.static_scene.push_back(Aabb{Vec3(0.16, -1, -1), Vec3(2, 1, 1)});
    const nbs::VoxelCollisionChecker checker(sc.space, cs);
    nbs::LinearScanPath path = sc.path;
    const auto r = nbs::replan(path, sc.aim, sc.targets, sc.space, checker, sc.sensor);
    CHECK(r.outcome == nbs::ReplanOutcome::dropped_in_collision);
    CHECK(r.rotations_tried == 81);
    CHECK(r.collision_checks == 81);
    CHECK(r.collision_free_fraction == 0.0);
  }
}

TEST_CASE("Alg. 3 with a PathAcceptor (a robot): a refused rotation is skipped, all refused is dropped_unreachable",
          "[replanning]") {
  WallScene sc;
  sc.space = space_with(sc.l, sc.bounds, {}, Vec3(0.5, 0, 0.05));  // nothing in the way: (0, 0) passes Alg. 3
  const Pose original = sc.path.start().pose();
  SECTION("the unrotated path refused: the next rotation in Alg. 3's order (0, +step) is taken") {
    const auto not_original = [&](const nbs::LinearScanPath& p) { return !p.start().pose().isApprox(original, 1e-12); };
    nbs::LinearScanPath path = sc.path;
    const auto r = nbs::replan(path, sc.aim, sc.targets, sc.space, nbs::NoCollisions{}, sc.sensor, {}, not_original);
    CHECK(r.outcome == nbs::ReplanOutcome::rotated);
    CHECK(r.beta_x_rad == 0.0);
    CHECK(r.beta_y_rad == nbs::ReplanSetting{}.angle_step_rad);
    CHECK(r.acceptor_checks == 2);
    CHECK(r.acceptor_refusals == 1);
  }
  SECTION("every path refused: dropped_unreachable, the path unchanged") {
    const auto none = [](const nbs::LinearScanPath&) { return false; };
    nbs::LinearScanPath path = sc.path;
    const auto r = nbs::replan(path, sc.aim, sc.targets, sc.space, nbs::NoCollisions{}, sc.sensor, {}, none);
    CHECK(r.outcome == nbs::ReplanOutcome::dropped_unreachable);
    CHECK(r.acceptor_checks == r.acceptor_refusals);
    CHECK(r.acceptor_checks == r.collision_checks);
    CHECK(path.start().pose().isApprox(original, 0.0));
  }
}

TEST_CASE("replan_candidates drops the enclosed candidate and keeps the order of the others", "[replanning]") {
  const WallScene sc;
  auto make = [&](const Vec3& shift, std::size_t index) {
    nbs::ScanCandidate c;
    Pose p = sc.path.start().pose();
    p.translation() += shift;
    c.path = nbs::LinearScanPath(nbs::Viewpoint(p), sc.path.end_position() + shift);
    c.aim = {sc.aim + shift, Vec3::UnitX()};
    for (const auto& t : sc.targets) c.targets.push_back({t.point + shift, t.normal});
    c.index = index;
    return c;
  };
  // 0: behind the wall (replanned), 1: aim hidden inside the wall itself (dropped), 2: free (unchanged).
  std::vector<nbs::ScanCandidate> cs{make(Vec3::Zero(), 0), make(Vec3(0.102, 0, 0), 1), make(Vec3(0, 0, 0.2), 2)};
  cs[1].targets.clear();
  const auto reports = nbs::replan_candidates(cs, sc.space, nbs::NoCollisions{}, sc.sensor);
  REQUIRE(reports.size() == 3);
  CHECK(reports[0].outcome == nbs::ReplanOutcome::rotated);
  CHECK(reports[1].outcome == nbs::ReplanOutcome::dropped_occluded);
  CHECK(reports[2].outcome == nbs::ReplanOutcome::unchanged);
  REQUIRE(cs.size() == 2);
  CHECK(cs[0].index == 0);
  CHECK(cs[1].index == 2);
}

TEST_CASE("oriented box vs AABB overlap (SAT) agrees with corner projections", "[replanning][collision]") {
  // Boxes of comparable size with close centres, so that edge–edge separations (the 9 cross axes) occur.
  std::mt19937_64 rng(15);
  std::uniform_real_distribution<double> size(0.01, 0.1);
  int overlap = 0, apart = 0;
  for (int i = 0; i < 20000; ++i) {
    nbs::SensorHeadBox head;
    head.center_m = Vec3::Zero();
    head.size_m = nbs_test::random_vec3(size, rng);
    const Pose p = nbs::test::random_pose(rng, Vec3::Constant(-0.1), Vec3::Constant(0.1));
    const Vec3 half = nbs_test::random_vec3(size, rng);
    const Aabb b{-0.5 * half, 0.5 * half};
    const bool sure = nbs::test::head_overlaps(head, p, b, -1e-9);
    const bool maybe = nbs::test::head_overlaps(head, p, b, 1e-9);
    if (sure != maybe) continue;
    REQUIRE(nbs::detail::overlaps(head.at(p), b) == sure);
    (sure ? overlap : apart) += 1;
  }
  CHECK(overlap > 1000);
  CHECK(apart > 1000);
}

TEST_CASE("VoxelCollisionChecker agrees with the brute-force box oracle on random poses", "[replanning][collision]") {
  // Occupied plate at z ≈ 0.05, free (p = 0.01) column above it, unknown elsewhere inside the bounds; a table.
  const Aabb bounds{Vec3(-0.1, -0.1, 0.0), Vec3(0.1, 0.1, 0.2)};
  const Space space = space_with(0.01, bounds, {Aabb{Vec3(-0.06, -0.06, 0.05), Vec3(0.06, 0.06, 0.06)}},
                                 Vec3(0, 0, 0.6), 0.01);
  nbs::CollisionSetting cs;
  cs.head.size_m = Vec3(0.05, 0.03, 0.08);
  cs.static_scene.push_back(Aabb{Vec3(-1, -1, -0.3), Vec3(1, 1, -0.05)});
  const nbs::VoxelCollisionChecker checker(space, cs);
  const auto obstacles = nbs::test::obstacle_boxes(space, cs);
  std::mt19937_64 rng(11);
  int hits = 0, misses = 0, skipped = 0;
  for (int i = 0; i < 400; ++i) {
    const Pose p = nbs::test::random_pose(rng, Vec3(-0.2, -0.2, -0.1), Vec3(0.2, 0.2, 0.35));
    const int o = nbs::test::oracle_collides(obstacles, cs.head, p, 1e-6);
    if (o < 0) {
      ++skipped;
      continue;
    }
    REQUIRE(checker.collides(p) == (o == 1));
    (o == 1 ? hits : misses) += 1;
  }
  CHECK(hits >= 40);
  CHECK(misses >= 40);
  CHECK(skipped <= 4);
}

TEST_CASE("collision_free_fraction counts 10 mm portions with both ends free", "[replanning][collision]") {
  const Space space(0.01, Aabb{Vec3(5, 5, 5), Vec3(5.1, 5.1, 5.1)});
  nbs::CollisionSetting cs;
  cs.head.size_m = Vec3::Zero();  // a point: collides where the path runs inside the box
  cs.static_scene.push_back(Aabb{Vec3(0.305, -1, -1), Vec3(0.495, 1, 1)});
  const nbs::VoxelCollisionChecker checker(space, cs);
  const nbs::LinearScanPath path(nbs::Viewpoint(), Vec3(1.0, 0, 0));
  // Poses at x = k/100; those in [0.305, 0.495] collide (k = 31..49); a portion k→k+1 is free iff both ends are.
  int free = 0;
  for (int k = 0; k < 100; ++k) {
    const auto inside = [](int j) { return j / 100.0 >= 0.305 && j / 100.0 <= 0.495; };
    free += (!inside(k) && !inside(k + 1)) ? 1 : 0;
  }
  CHECK(nbs::collision_free_fraction(checker, path, 0.01) == Approx(free / 100.0));
  CHECK(nbs::collision_free_fraction(checker, nbs::LinearScanPath(nbs::Viewpoint()), 0.01) == 1.0);
  CHECK(nbs::path_portions(0.3, 0.01) == 30);
  CHECK(nbs::path_portions(0.0, 0.01) == 1);
}

TEST_CASE("replanning and collision checking reject bad input", "[replanning][collision]") {
  const WallScene sc;
  nbs::CollisionSetting cs;
  const nbs::VoxelCollisionChecker checker(sc.space, cs);
  Pose nan_pose = Pose::Identity();
  nan_pose.translation().x() = std::nan("");
  CHECK_THROWS_AS((void)checker.collides(nan_pose), nbs::InvalidArgument);
  Pose skew = Pose::Identity();
  skew.linear()(0, 1) = 0.5;
  CHECK_THROWS_AS((void)checker.collides(skew), nbs::InvalidArgument);
  cs.head.size_m = Vec3(0.1, -0.01, 0.1);
  CHECK_THROWS_AS(nbs::VoxelCollisionChecker(sc.space, cs), nbs::InvalidArgument);
  cs.head.size_m = Vec3(0.1, 0.1, 0.1);
  cs.obstacle_probability = 1.5;
  CHECK_THROWS_AS(nbs::VoxelCollisionChecker(sc.space, cs), nbs::InvalidArgument);
  cs.obstacle_probability = 0.05;
  cs.static_scene.push_back(Aabb{Vec3(0, 0, 0), Vec3(1, std::numeric_limits<double>::infinity(), 1)});
  CHECK_THROWS_AS(nbs::VoxelCollisionChecker(sc.space, cs), nbs::InvalidArgument);
  CHECK_THROWS_AS((void)nbs::collision_free_fraction(nbs::NoCollisions{}, sc.path, 0.0), nbs::InvalidArgument);

  nbs::LinearScanPath path = sc.path;
  const auto run = [&](const Vec3& aim, std::vector<nbs::SurfaceTarget> targets, nbs::ReplanSetting s = {}) {
    return nbs::replan(path, aim, targets, sc.space, nbs::NoCollisions{}, sc.sensor, s);
  };
  CHECK_THROWS_AS((void)run(sc.aim, {}), nbs::InvalidArgument);
  CHECK_THROWS_AS((void)run(sc.aim, {{Vec3(std::nan(""), 0, 0), Vec3::UnitX()}}), nbs::InvalidArgument);
  CHECK_THROWS_AS((void)run(Vec3(std::nan(""), 0, 0), sc.targets), nbs::InvalidArgument);
  CHECK_THROWS_AS((void)run(Vec3(0.5, 0, 0.05), sc.targets), nbs::InvalidArgument);  // aim behind the sensor
  nbs::ReplanSetting bad;
  bad.angle_steps = 9;  // 90°
  CHECK_THROWS_AS((void)run(sc.aim, sc.targets, bad), nbs::InvalidArgument);
  bad = {};
  bad.min_visible_fraction = std::nan("");
  CHECK_THROWS_AS((void)run(sc.aim, sc.targets, bad), nbs::InvalidArgument);
  bad = {};
  bad.portion_m = -0.01;
  CHECK_THROWS_AS((void)run(sc.aim, sc.targets, bad), nbs::InvalidArgument);
  nbs::SensorGeometry bad_sensor = sc.sensor;
  bad_sensor.fov_x_rad = -1.0;
  CHECK_THROWS_AS((void)nbs::replan(path, sc.aim, sc.targets, sc.space, nbs::NoCollisions{}, bad_sensor),
                  nbs::InvalidArgument);
  CHECK((path.start().pose().matrix() - sc.path.start().pose().matrix()).cwiseAbs().maxCoeff() == 0.0);
}
