// SPDX-License-Identifier: BSD-3-Clause
// LinkCollisionChecker and RobotPathChecker (issue 19, item 2) against brute-force oracles: every voxel centre of a
// ProbabilisticVoxelSpace whose voxels the test sets occupied / free / unknown, with shape distances computed
// independently (closest points in the world frame); the planar 3R arm (planar_robot.hpp) through walls, free and
// unknown space, over the table and along a scan path.
#include "nbs_catch.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "nbs/robot/free_flying.hpp"
#include "nbs/robot/link_collision.hpp"
#include "nbs/space/backend.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"
#include "planar_robot.hpp"
#include "sim/test_meshes.hpp"
#include "nbs_random.hpp"

using namespace nbs;
using nbs::test::PlanarArm;

namespace {

using Space = ProbabilisticVoxelSpace<>;
enum class Cell { unknown, free, occupied };
struct KeyLess {
  bool operator()(const VoxelKey& a, const VoxelKey& b) const { return a.pack() < b.pack(); }
};
using CellMap = std::map<VoxelKey, Cell, KeyLess>;

ThesisState occupied_state() {
  ThesisState s;
  s.surf = 6000;  // log L_surf ≈ 5.9 nat: p ≈ 1
  return s;
}
ThesisState free_state() {
  ThesisState s;
  s.free = -6000;  // log L_free ≈ −5.9 nat: p ≈ 0
  s.direction = 0;
  return s;
}

// Sets voxel k of `space` (and the test's own record) to `c`; unknown voxels are never written.
void set_cell(Space& space, CellMap& record, const VoxelKey& k, Cell c) {
  record[k] = c;
  if (c == Cell::unknown) return;
  set_voxel_state(space.mutable_backend(), k, c == Cell::occupied ? occupied_state() : free_state());
}

// Sets every voxel of the space's bounds at random (fixed seed via rng): occupied with probability `occupied`,
// unknown with `unknown`, else free.
void random_cells(Space& space, CellMap& record, std::mt19937_64& rng, double occupied, double unknown) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const KeyBox b = space.bounds_keys();
  for (int z = b.min.z; z <= b.max.z; ++z)
    for (int y = b.min.y; y <= b.max.y; ++y)
      for (int x = b.min.x; x <= b.max.x; ++x) {
        const double r = u(rng);
        set_cell(space, record, {x, y, z},
                 r < occupied ? Cell::occupied : r < occupied + unknown ? Cell::unknown : Cell::free);
      }
}

// Every key of the space's bounds, classified from the test's record (not set = unknown); checks that the space
// agrees (p above/below 0.05, observed or not).
std::vector<std::pair<VoxelKey, Cell>> all_cells(const Space& space, const CellMap& record) {
  std::vector<std::pair<VoxelKey, Cell>> out;
  const KeyBox b = space.bounds_keys();
  for (int z = b.min.z; z <= b.max.z; ++z)
    for (int y = b.min.y; y <= b.max.y; ++y)
      for (int x = b.min.x; x <= b.max.x; ++x) {
        const VoxelKey k{x, y, z};
        const auto it = record.find(k);
        const Cell c = it == record.end() ? Cell::unknown : it->second;
        out.emplace_back(k, c);
        const double p = space.probability(k);
        REQUIRE((c == Cell::free ? p < 0.05 : p > 0.05));
        REQUIRE(space.observed(k) == (c != Cell::unknown));
      }
  return out;
}

// Distance from the world point p to the solid shape, computed as |p − closest point| in the world frame (0 inside):
// independent of detail::shape_distance (which works with signed distances in the shape frame).
double oracle_distance(const PlacedShape& s, const Vec3& p) {
  const Vec3 c = s.T_WG.translation();
  const Mat3 R = s.T_WG.linear();
  const Vec3 a = R.col(2);
  const LinkShape& g = s.shape;
  switch (g.kind) {
    case LinkShape::Kind::sphere: return std::max(0.0, (p - c).norm() - g.radius);
    case LinkShape::Kind::capsule: {
      const Vec3 e0 = c - 0.5 * g.length * a, e1 = c + 0.5 * g.length * a;
      const double t = std::clamp((p - e0).dot(e1 - e0) / std::max(1e-300, (e1 - e0).squaredNorm()), 0.0, 1.0);
      return std::max(0.0, (p - (e0 + t * (e1 - e0))).norm() - g.radius);
    }
    case LinkShape::Kind::cylinder: {
      const double h = (p - c).dot(a);
      const Vec3 radial = (p - c) - h * a;
      const double rn = radial.norm();
      const Vec3 closest =
          c + std::clamp(h, -0.5 * g.length, 0.5 * g.length) * a + (rn > g.radius ? (g.radius / rn) * radial : radial);
      return (p - closest).norm();
    }
    case LinkShape::Kind::box: {
      const Eigen::AlignedBox3d box(-0.5 * g.size, 0.5 * g.size);
      return box.exteriorDistance(Vec3(R.transpose() * (p - c)));
    }
    case LinkShape::Kind::mesh: break;
  }
  return std::numeric_limits<double>::infinity();
}

// A free-flying body: FreeFlyingSensor's kinematics carrying one shape fixed in the sensor frame.
struct FlyingBody {
  FreeFlyingSensor base;
  LinkShape shape;
  [[nodiscard]] std::size_t joint_count() const { return 6; }
  [[nodiscard]] JointLimits joint_limits() const { return base.joint_limits(); }
  [[nodiscard]] Pose fk(const JointVector& q) const { return base.fk(q); }
  [[nodiscard]] std::optional<JointVector> ik(const Pose& T, const JointVector& seed) const {
    return base.ik(T, seed);
  }
  [[nodiscard]] std::vector<PlacedShape> collision_shapes(const JointVector& q) const {
    return {PlacedShape{"body", shape, base.fk(q) * shape.T_LG}};
  }
  [[nodiscard]] Pose hand_eye() const { return Pose::Identity(); }
};
static_assert(Robot<FlyingBody>);

LinkShape make_shape(LinkShape::Kind kind) {
  LinkShape s;
  s.kind = kind;
  s.T_LG.translation() = Vec3(0.003, -0.002, 0.01);
  s.T_LG.linear() = Eigen::AngleAxisd(0.4, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  s.radius = 0.012;
  s.length = 0.03;
  s.size = Vec3(0.02, 0.012, 0.035);
  return s;
}

JointVector jv(double a, double b, double c) {
  JointVector q(3);
  q << a, b, c;
  return q;
}

// Planar-arm scene: 1 cm voxels over x ∈ [0.2, 0.5), y ∈ [−0.05, 0.05), z ∈ [−0.1, 0.3): an occupied wall at
// x ∈ [0.45, 0.46) below z = 0.1, unknown voxels above z = 0.1, free voxels elsewhere.
struct WallScene {
  Space space{0.01, Aabb{Vec3(0.2, -0.05, -0.1), Vec3(0.4999, 0.0499, 0.2999)}};
  CellMap record;
  WallScene() {
    const KeyBox b = space.bounds_keys();
    for (int z = b.min.z; z <= b.max.z; ++z)
      for (int y = b.min.y; y <= b.max.y; ++y)
        for (int x = b.min.x; x <= b.max.x; ++x)
          set_cell(space, record, {x, y, z}, z >= 10 ? Cell::unknown : x == 45 ? Cell::occupied : Cell::free);
  }
};

LinkCollisionSetting no_table() {
  LinkCollisionSetting s;
  s.check_table = false;
  return s;
}

}  // namespace

TEST_CASE("LinkCollisionChecker agrees with a brute-force oracle over every voxel centre (all shape kinds)",
          "[robot][collision]") {
  // 1 cm voxels in [−0.1, 0.1)³: 2 % occupied, 2 % unknown, the rest free, drawn with a fixed seed.
  Space space(0.01, Aabb{Vec3::Constant(-0.1), Vec3::Constant(0.0999)});
  CellMap record;
  std::mt19937_64 rng(20261205);
  random_cells(space, record, rng, 0.02, 0.02);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const auto cells = all_cells(space, record);
  REQUIRE(cells.size() == 8000);
  const double half_diag = 0.5 * std::sqrt(3.0) * 0.01;

  for (const auto kind :
       {LinkShape::Kind::sphere, LinkShape::Kind::capsule, LinkShape::Kind::cylinder, LinkShape::Kind::box})
    for (const double margin : {0.0, 0.004})
      for (const bool unknown : {true, false}) {
        const FlyingBody body{{}, make_shape(kind)};
        LinkCollisionSetting s = no_table();
        s.safety_margin_m = margin;
        s.unknown_is_obstacle = unknown;
        const LinkCollisionChecker checker(body, space, s);
        const double reach = margin + half_diag;
        int hits = 0, misses = 0;
        for (int trial = 0; trial < 150; ++trial) {
          // Positions up to 3 cm beyond the bounds (clipping), random rotation vectors.
          JointVector q(6);
          for (int i = 0; i < 3; ++i) q[i] = -0.13 + 0.26 * u(rng);
          Vec3 w = nbs_test::random_vec3(u, rng) - Vec3::Constant(0.5);
          w = w.normalized() * std::numbers::pi * u(rng);
          q.tail<3>() = w;
          const PlacedShape placed = body.collision_shapes(q).front();
          // Oracle: some obstacle voxel's centre within `reach` of the shape; skip configurations within 1e-9 m of
          // the decision boundary. Conservative direction: a dense sample (5³ points) of each obstacle cube within
          // the margin of the shape implies a hit.
          bool expect = false, ambiguous = false, cube_touch = false;
          for (const auto& [k, c] : cells) {
            if (!(c == Cell::occupied || (unknown && c == Cell::unknown))) continue;
            const double d = oracle_distance(placed, space.grid().center(k));
            ambiguous = ambiguous || std::abs(d - reach) < 1e-9;
            expect = expect || d <= reach;
            if (d > reach + 0.01) continue;
            for (int i = 0; i < 125 && !cube_touch; ++i) {
              const Vec3 f(i % 5, (i / 5) % 5, i / 25);
              cube_touch = oracle_distance(placed, space.grid().center(k) + (f / 4.0 - Vec3::Constant(0.5)) * 0.01) <=
                           margin;
            }
          }
          if (ambiguous) continue;
          const auto contact = checker.first_contact(q);
          INFO("kind " << int(kind) << " margin " << margin << " unknown " << unknown << " q " << q.transpose());
          REQUIRE(contact.has_value() == expect);
          if (cube_touch) REQUIRE(contact.has_value());
          if (contact) {
            CHECK(contact->link == "body");
            CHECK(contact->with == LinkContact::With::voxel);
            CHECK(oracle_distance(placed, space.grid().center(contact->voxel)) <= reach + 1e-9);
            CHECK(checker.is_obstacle(contact->voxel));
          }
          (expect ? hits : misses) += 1;
        }
        INFO("kind " << int(kind) << " margin " << margin << " unknown " << unknown);
        CHECK(hits >= 15);  // both outcomes well represented
        CHECK(misses >= 15);
      }
}

TEST_CASE("LinkCollisionChecker: a link through an occupied wall collides, through free space not; unknown space "
          "counts unless switched off",
          "[robot][collision]") {
  const WallScene scene;
  REQUIRE(all_cells(scene.space, scene.record).size() == 30 * 10 * 40);
  const PlanarArm arm;
  constexpr double pi = std::numbers::pi;
  LinkCollisionSetting off = no_table();
  off.unknown_is_obstacle = false;
  const LinkCollisionChecker with_unknown(arm, scene.space, no_table()), without_unknown(arm, scene.space, off);

  // Stretched along +x at z = 0: link2 (x ∈ [0.4, 0.7]) crosses the wall.
  const JointVector wall = jv(pi / 2, 0, 0);
  for (const auto* c : {&with_unknown, &without_unknown}) {
    const auto hit = c->first_contact(wall);
    REQUIRE(hit);
    CHECK(hit->link == "link2");
    CHECK(hit->voxel.x == 45);
  }
  // Link1 along +x to (0.4, 0, 0), link2 straight down: only free voxels within reach (wall centre 0.035 m away).
  const JointVector down = jv(pi / 2, pi / 2, 0);
  CHECK_FALSE(with_unknown.collides(down));
  CHECK_FALSE(without_unknown.collides(down));
  // Link2 straight up from (0.4, 0, 0) through the unknown voxels above z = 0.1.
  const JointVector up = jv(pi / 2, -pi / 2, 0);
  const auto hit = with_unknown.first_contact(up);
  REQUIRE(hit);
  CHECK(hit->link == "link2");
  CHECK(hit->voxel.z >= 10);
  CHECK_FALSE(without_unknown.collides(up));
  // The wall's voxel centres are 0.035 m from the downward link's surface: clear with a 2 cm margin (reach 0.0287 m),
  // hit with 3 cm (0.0387 m).
  LinkCollisionSetting m = no_table();
  m.safety_margin_m = 0.02;
  CHECK_FALSE(LinkCollisionChecker(arm, scene.space, m).collides(down));
  m.safety_margin_m = 0.03;
  const auto near = LinkCollisionChecker(arm, scene.space, m).first_contact(down);
  REQUIRE(near);
  CHECK(near->voxel.x == 45);
}

TEST_CASE("LinkCollisionChecker: the table half-space against the links' lowest points", "[robot][collision]") {
  const Space far(0.01, Aabb{Vec3(5, 5, 5), Vec3(5.1, 5.1, 5.1)});  // no voxel near the arm
  const PlanarArm arm;
  LinkCollisionSetting s;
  s.table_height_m = 0.1;
  s.safety_margin_m = 0.01;
  s.table_exempt_links = {"link1"};
  const LinkCollisionChecker checker(arm, far, s);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> ang(-std::numbers::pi, std::numbers::pi);
  int hits = 0, misses = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const Vec3 a = nbs_test::random_vec3(ang, rng);
    const JointVector q = jv(a.x(), a.y(), a.z());
    // Oracle: the joint positions by hand; a capsule's lowest point is its lower end minus the radius 0.02.
    const double phi1 = q[0], phi2 = q[0] + q[1], phi3 = phi2 + q[2];
    const double z1 = arm.l[0] * std::cos(phi1), z2 = z1 + arm.l[1] * std::cos(phi2),
                 z3 = z2 + arm.l[2] * std::cos(phi3);
    const double lowest2 = std::min(z1, z2) - 0.02, lowest3 = std::min(z2, z3) - 0.02;
    if (std::abs(lowest2 - 0.11) < 1e-9 || std::abs(lowest3 - 0.11) < 1e-9) continue;
    const bool expect = std::min(lowest2, lowest3) < 0.11;
    const auto c = checker.first_contact(q);
    REQUIRE(c.has_value() == expect);
    if (c) {
      CHECK(c->with == LinkContact::With::table);
      CHECK(c->link == (lowest2 < 0.11 ? "link2" : "link3"));
    }
    (expect ? hits : misses) += 1;
  }
  CHECK(hits > 50);
  CHECK(misses > 50);
  // Upright, link1 reaches 0.02 m below its base: exempt by name, and checked when not exempt.
  s.table_height_m = 0.0;
  s.safety_margin_m = 0.0;
  CHECK_FALSE(LinkCollisionChecker(arm, far, s).collides(jv(0, 0, 0)));
  s.table_exempt_links.clear();
  CHECK(LinkCollisionChecker(arm, far, s).first_contact(jv(0, 0, 0))->link == "link1");
  // A finite table (x ≤ 0.3): the arm folded down at x ≈ 0.4 is beside it; over it, it hits.
  s.table_exempt_links = {"link1"};
  s.table_max_xy.x() = 0.3;
  const JointVector folded = jv(std::numbers::pi / 2, std::numbers::pi / 2, 0);  // link2 down at x = 0.4
  CHECK_FALSE(LinkCollisionChecker(arm, far, s).collides(folded));
  s.table_max_xy.x() = 0.45;
  CHECK(LinkCollisionChecker(arm, far, s).collides(folded));
}

TEST_CASE("RobotPathChecker: a scan path whose middle step drives a link into an occupied voxel fails there",
          "[robot][collision]") {
  // The sensor looks down (φ = π) at z = 0.2 and moves along x from 0.3 to 0.5; one occupied voxel below the path
  // near x = 0.4, its neighbours free.
  const PlanarArm arm;
  Space space(0.01, Aabb{Vec3(0.35, -0.03, 0.12), Vec3(0.4499, 0.0299, 0.1799)});
  CellMap record;
  const KeyBox b = space.bounds_keys();
  for (int z = b.min.z; z <= b.max.z; ++z)
    for (int y = b.min.y; y <= b.max.y; ++y)
      for (int x = b.min.x; x <= b.max.x; ++x)
        set_cell(space, record, {x, y, z}, (VoxelKey{x, y, z} == VoxelKey{40, 0, 17}) ? Cell::occupied : Cell::free);
  Pose start = Pose::Identity();
  start.linear() = PlanarArm::rot_y(std::numbers::pi);
  start.translation() = Vec3(0.3, 0, 0.2);
  const LinearScanPath path(Viewpoint(start), Vec3(0.5, 0, 0.2));
  const JointVector seed = jv(0.3, 1.0, 1.8);

  LinkCollisionSetting s;
  s.table_exempt_links = {"link1"};
  const RobotPathChecker checker(arm, space, s);
  const ScanPathReach free_run = check_scan_path(arm, path, seed);
  REQUIRE(free_run.ok());
  REQUIRE(free_run.samples == 21);

  // Oracle: the first sample at which a link's capsule (by hand from the joints) comes within 0.02 m + √3/2 cm of
  // the voxel centre (0.405, 0.005, 0.175).
  const Vec3 v(0.405, 0.005, 0.175);
  const double reach = 0.02 + 0.5 * std::sqrt(3.0) * 0.01;
  std::optional<std::size_t> first;
  std::string link;
  for (std::size_t i = 0; i < free_run.joints.size() && !first; ++i) {
    const JointVector& q = free_run.joints[i];
    Vec3 p = Vec3::Zero();
    double phi = 0;
    for (int j = 0; j < 3 && !first; ++j) {
      phi += q[j];
      const Vec3 e = p + arm.l[static_cast<std::size_t>(j)] * PlanarArm::dir(phi);
      const double t = std::clamp((v - p).dot(e - p) / (e - p).squaredNorm(), 0.0, 1.0);
      if ((v - (p + t * (e - p))).norm() <= reach) {
        first = i;
        link = "link" + std::to_string(j + 1);
      }
      p = e;
    }
  }
  REQUIRE(first);
  REQUIRE(*first > 0);
  REQUIRE(*first < free_run.samples - 1);
  const ScanPathReach r = checker.check(path, seed);
  CHECK(r.failure == PathFailure::collision);
  CHECK(to_string(r.failure) == "collision");
  CHECK(r.step == *first);
  CHECK(r.link == link);
  CHECK(r.value == Approx(double(*first) / 20.0));
  CHECK(r.joints.size() == *first);

  // Without the voxel the path is flown, with the same joints as without a collision check.
  Space empty(0.01, Aabb{Vec3(0.35, -0.03, 0.12), Vec3(0.4499, 0.0299, 0.1799)});
  for (const auto& [k, c] : record) set_voxel_state(empty.mutable_backend(), k, free_state());
  const ScanPathReach ok = RobotPathChecker(arm, empty, s).check(path, seed);
  REQUIRE(ok.ok());
  REQUIRE(ok.joints.size() == free_run.joints.size());
  for (std::size_t i = 0; i < ok.joints.size(); ++i) CHECK(ok.joints[i] == free_run.joints[i]);
}

TEST_CASE("LinkCollisionChecker / RobotPathChecker: bad input gives a clear error naming the value",
          "[robot][collision]") {
  const PlanarArm arm;
  const Space space(0.01, Aabb{Vec3::Constant(-0.1), Vec3::Constant(0.1)});
  auto refused = [&](LinkCollisionSetting s, const char* text) {
    CHECK_THROWS_WITH(LinkCollisionChecker(arm, space, s), nbs_test::Contains(text));
  };
  LinkCollisionSetting s;
  s.obstacle_probability = 1.5;
  refused(s, "obstacle_probability");
  s = {};
  s.safety_margin_m = -0.01;
  refused(s, "safety_margin_m");
  s = {};
  s.table_height_m = std::numeric_limits<double>::quiet_NaN();
  refused(s, "table_height_m");
  s = {};
  s.table_min_xy.x() = 1.0;
  s.table_max_xy.x() = 0.0;
  refused(s, "table extent along x");

  FlyingBody body{{}, make_shape(LinkShape::Kind::mesh)};
  body.shape.mesh_path = "package://arm/forearm.stl";
  CHECK_THROWS_WITH(LinkCollisionChecker(body, space), nbs_test::Contains("forearm.stl"));
  s = {};
  s.skip_mesh_shapes = true;
  const LinkCollisionChecker skipping(body, space, s);
  CHECK_FALSE(skipping.collides(JointVector::Zero(6)));  // documented: meshes are not checked
  FlyingBody negative{{}, make_shape(LinkShape::Kind::sphere)};
  negative.shape.radius = -1.0;
  CHECK_THROWS_WITH(LinkCollisionChecker(negative, space), nbs_test::Contains("link 'body'"));

  const LinkCollisionChecker checker(arm, space);
  CHECK_THROWS_WITH(checker.collides(JointVector::Zero(2)), nbs_test::Contains("LinkCollisionChecker q"));
  ScanPathReachSetting bad;
  bad.max_sample_step_m = 0.0;
  CHECK_THROWS_WITH(RobotPathChecker(arm, space, {}, bad), nbs_test::Contains("max_sample_step_m"));
}

namespace {

// A closed box mesh (12 outward triangles, corners not shared: CollisionMesh welds them) of full edge lengths
// `size`, centred at `c`, appended to m.
void append_box_mesh(IndexedMesh& m, const Vec3& size, const Vec3& c = Vec3::Zero()) {
  const IndexedMesh box = test::box_mesh(c - 0.5 * size, c + 0.5 * size);
  const auto o = static_cast<std::uint32_t>(m.vertices.size());
  m.vertices.insert(m.vertices.end(), box.vertices.begin(), box.vertices.end());
  for (const auto& t : box.triangles) m.triangles.push_back({o + t[0], o + t[1], o + t[2]});
}

Pose random_pose(std::mt19937_64& rng, double spread) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Pose T = Pose::Identity();
  T.linear() = nbs_test::random_quaternion(u, rng).normalized().toRotationMatrix();
  T.translation() = spread * nbs_test::random_vec3(u, rng);
  return T;
}

}  // namespace

TEST_CASE("mesh shapes: a 12-triangle box mesh hits exactly the voxels of the primitive box (seeded random poses); "
          "two boxes in one mesh and an open square likewise",
          "[robot][collision][mesh]") {
  // Oracle: the primitive box's exact distance (detail::shape_distance, itself checked against the brute-force
  // closest point above). Voxel centres of 1 cm voxels in [−0.1, 0.1)³, reach = √3/2 · l_v (+ a margin).
  const Space space(0.01, Aabb{Vec3::Constant(-0.1), Vec3::Constant(0.0999)});
  const Vec3 size(0.05, 0.035, 0.045);  // deep enough for voxel centres inside beyond the reach
  IndexedMesh one, two, square;
  append_box_mesh(one, size);
  const Vec3 offset(0.0, 0.0, 0.06);  // a second box above the first: a +z ray crosses four faces
  append_box_mesh(two, size);
  append_box_mesh(two, size, offset);
  square.vertices = {Vec3(-0.025, -0.02, 0), Vec3(0.025, -0.02, 0), Vec3(0.025, 0.02, 0), Vec3(-0.025, 0.02, 0)};
  square.triangles = {{0, 1, 2}, {0, 2, 3}};
  const CollisionMesh mesh_one(one), mesh_two(two), mesh_square(square);
  REQUIRE(mesh_one.closed());
  REQUIRE(mesh_two.closed());
  REQUIRE_FALSE(mesh_square.closed());
  LinkShape box;
  box.size = size;
  LinkShape flat;
  flat.size = Vec3(0.05, 0.04, 0.0);  // the open square is a box of zero thickness (a shell has no inside)

  std::mt19937_64 rng(20261205);
  long inside = 0, hits = 0, compared = 0, distance_mismatches = 0, hit_mismatches = 0;
  std::string first_mismatch;
  for (int trial = 0; trial < 16; ++trial) {
    const Pose T = random_pose(rng, 0.05);
    const Pose T_GW = T.inverse();
    Pose T2 = T;
    T2.translation() += T.linear() * offset;
    const double reach = (trial % 2 == 0 ? 0.0 : 0.004) + 0.5 * std::sqrt(3.0) * 0.01;
    // The table test uses the world AABB: the transformed vertices' bounds equal the primitive's exact bounds.
    const Aabb a = detail::shape_bounds(box, T), b = mesh_one.world_bounds(T);
    REQUIRE((a.min - b.min).norm() < 1e-12);
    REQUIRE((a.max - b.max).norm() < 1e-12);
    const KeyBox kb = space.bounds_keys();
    for (int z = kb.min.z; z <= kb.max.z; ++z)
      for (int y = kb.min.y; y <= kb.max.y; ++y)
        for (int x = kb.min.x; x <= kb.max.x; ++x) {
          const Vec3 c = space.grid().center(VoxelKey{x, y, z});
          const Vec3 g = T_GW * c;
          const double d1 = detail::shape_distance(box, T, c), d2 = detail::shape_distance(box, T2, c);
          const double d12 = std::min(d1, d2), df = detail::shape_distance(flat, T, c);
          for (const auto& entry : {std::pair{&mesh_one, d1}, {&mesh_two, d12}, {&mesh_square, df}}) {
            const auto* mesh = entry.first;  // not structured bindings: clang before 16 cannot capture those
            const double d = entry.second;
            const auto mismatch = [&](const char* what, long& count) {
              if (count++ == 0)
                first_mismatch = detail::concat(what, ": trial ", trial, " voxel ", x, " ", y, " ", z, " oracle ", d,
                                                " mesh ", mesh->distance(g), " reach ", reach);
            };
            // Signed distances agree (inside included) to rounding.
            if (!(std::abs(mesh->distance(g) - d) <= 1e-12)) mismatch("distance", distance_mismatches);
            if (std::abs(d - reach) < 1e-9) continue;  // on the decision boundary: rounding decides
            if (mesh->within(g, reach) != (d <= reach)) mismatch("hit", hit_mismatches);
            ++compared;
          }
          inside += d1 < -reach;
          hits += d1 <= reach;
        }
  }
  INFO(first_mismatch);
  CHECK(distance_mismatches == 0);
  CHECK(hit_mismatches == 0);
  CHECK(compared > 350'000);
  CHECK(inside > 100);  // 165: the inside test decided many voxels
  CHECK(hits > 2000);  // 4033
}

TEST_CASE("LinkCollisionChecker: a link with a box mesh gives the same contacts as the primitive box (voxels and "
          "table)",
          "[robot][collision][mesh]") {
  Space space(0.01, Aabb{Vec3::Constant(-0.1), Vec3::Constant(0.0999)});
  CellMap record;
  std::mt19937_64 rng(7);
  random_cells(space, record, rng, 0.01, 0.01);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Vec3 size(0.05, 0.035, 0.045);
  FlyingBody primitive{{}, make_shape(LinkShape::Kind::box)};
  primitive.shape.size = size;
  FlyingBody meshed{{}, primitive.shape};
  IndexedMesh m;
  append_box_mesh(m, size);
  meshed.shape.kind = LinkShape::Kind::mesh;
  meshed.shape.mesh_path = "box.stl";
  meshed.shape.size = Vec3::Ones();
  meshed.shape.mesh = std::make_shared<const CollisionMesh>(m);
  LinkCollisionSetting s;
  s.table_height_m = -0.06;
  s.safety_margin_m = 0.002;
  const LinkCollisionChecker a(primitive, space, s), b(meshed, space, s);
  int contacts = 0, table = 0;
  for (int trial = 0; trial < 300; ++trial) {
    JointVector q(6);
    for (int i = 0; i < 3; ++i) q[i] = -0.12 + 0.24 * u(rng);
    Vec3 w = nbs_test::random_vec3(u, rng) - Vec3::Constant(0.5);
    q.tail<3>() = w.normalized() * std::numbers::pi * u(rng);
    const auto ca = a.first_contact(q), cb = b.first_contact(q);
    INFO("q " << q.transpose());
    REQUIRE(ca.has_value() == cb.has_value());
    if (!ca) continue;
    ++contacts;
    table += ca->with == LinkContact::With::table;
    CHECK(ca->with == cb->with);
    CHECK(ca->voxel == cb->voxel);
  }
  CHECK(contacts >= 30);
  CHECK(table >= 10);
  CHECK(contacts - table >= 10);
  LinkCollisionSetting skip = s;
  skip.skip_mesh_shapes = true;
  const LinkCollisionChecker skipping(meshed, space, skip);
  JointVector q = JointVector::Zero(6);
  q[2] = -0.08;  // through the table
  CHECK(a.collides(q));
  CHECK(b.collides(q));
  CHECK_FALSE(skipping.collides(q));  // documented: skipped meshes are not checked
}

TEST_CASE("CollisionMesh: a scale that overflows or underflows the vertices is refused naming the mesh; a non-finite "
          "query point is outside",
          "[robot][collision][mesh]") {
  IndexedMesh square;
  square.vertices = {Vec3(-1.5, -1.5, 0), Vec3(1.5, -1.5, 0), Vec3(1.5, 1.5, 0), Vec3(-1.5, 1.5, 0)};
  square.triangles = {{0, 1, 2}, {0, 2, 3}};
  // 1.5 · 1.7e308 overflows; ±1.5e308 are finite but their extent 3e308 is not; denorm_min · 0.15 rounds to 0.
  CHECK_THROWS_WITH(CollisionMesh(square, Vec3(1.7e308, 1.0, 1.0), "huge.stl"),
                    nbs_test::Contains("huge.stl: vertex 0 scaled by"));
  CHECK_THROWS_WITH(CollisionMesh(square, Vec3(1e308, 1.0, 1.0), "wide.stl"),
                    nbs_test::Contains("wide.stl: the scaled bounds' extent (inf"));
  IndexedMesh small = square;
  for (Vec3& v : small.vertices) v *= 0.1;
  CHECK_THROWS_WITH(CollisionMesh(small, Vec3::Constant(std::numeric_limits<double>::denorm_min()), "tiny.stl"),
                    nbs_test::Contains("tiny.stl: the scaled bounds' extent (0 0 0) gives a grid cell of 0 m"));

  IndexedMesh box;
  append_box_mesh(box, Vec3(0.05, 0.04, 0.03));
  const CollisionMesh mesh(box);
  REQUIRE(mesh.closed());
  REQUIRE(mesh.contains(Vec3::Zero()));
  REQUIRE(mesh.within(Vec3::Zero(), 0.0));
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (const Vec3& g : {Vec3(nan, 0, 0), Vec3(0, 0, nan), Vec3(inf, 0, 0), Vec3(0, 0, -inf)}) {
    INFO(g.transpose());
    CHECK_FALSE(mesh.contains(g));
    CHECK_FALSE(mesh.within(g, 0.01));
    CHECK_FALSE(mesh.within(g, inf));
    CHECK(mesh.surface_distance(g) == inf);
    CHECK(mesh.distance(g) == inf);
  }
  CHECK_FALSE(mesh.within(Vec3::Zero(), nan));
}
