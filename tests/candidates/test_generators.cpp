// SPDX-License-Identifier: BSD-3-Clause
// The CandidateGenerator concept and its models: sphere baseline, bad input, area sensors, determinism, the
// planarity reading of Eqs. 4.19-4.21.
#include "nbs_catch.hpp"

#include <cmath>
#include <limits>

#include "nbs/space/probabilistic_voxel_space.hpp"
#include "../mesh/mesh_test_util.hpp"
#include "nbs/candidates/generators.hpp"

using nbs::Vec3;

namespace {

using Space = nbs::ProbabilisticVoxelSpace<>;
using Context = nbs::PlanningContext<nbs::StreamingMesh, Space>;

static_assert(nbs::CandidateGenerator<nbs::BoundarySearch, nbs::StreamingMesh, Space>);
static_assert(nbs::CandidateGenerator<nbs::HoleRescan, nbs::StreamingMesh, Space>);
static_assert(nbs::CandidateGenerator<nbs::SphereSearch, nbs::StreamingMesh, Space>);
static_assert(!nbs::CandidateGenerator<int, nbs::StreamingMesh, Space>);

const nbs::SensorGeometry kLine{nbs::SensorGeometry::Kind::line, {0.15, 0.45}, 0.5, 0.0};

void check_pose_and_aim(const nbs::ScanCandidate& c, double d_s) {
  const nbs::Viewpoint& v = c.path.start();
  REQUIRE(v.pose().matrix().allFinite());
  REQUIRE(c.path.end_position().allFinite());
  CHECK((v.pose().linear().transpose() * v.pose().linear() - nbs::Mat3::Identity()).cwiseAbs().maxCoeff() < 1e-9);
  CHECK(v.pose().linear().determinant() == Approx(1.0).margin(1e-9));
  const Vec3 rel = c.aim.point - v.position();
  CHECK(rel.dot(v.view_direction()) == Approx(d_s).margin(1e-9));
  CHECK((rel - d_s * v.view_direction()).cross(v.y_axis()).norm() < 1e-9);
}

struct PlaneScan {
  nbs::Parameters params;
  nbs::StreamingMesh mesh{params};
  Space space{0.005};
  PlaneScan() {
    nbs::test::PlanePatch plane(0.2, 0.2);
    nbs::test::StripeSensor s;
    s.rays = 160;
    s.step_m = 0.0005;
    mesh.integrate(nbs::test::scan_path(plane, nbs::test::down_at(0, 0.03, 0.15), 0.06, s, 5));
  }
  [[nodiscard]] Context context(const nbs::SensorGeometry& g = kLine) const {
    return Context{mesh, space, params, mesh.current_sensor(), 0.06, g};
  }
};

}  // namespace

TEST_CASE("sphere generator: 81 paths around the unknown area, aim at d_s (Sec. 4.7.2)", "[generators]") {
  nbs::Parameters params;
  nbs::StreamingMesh mesh{params};
  const Space space(0.005);
  Context ctx{mesh, space, params, nbs::Pose::Identity(), 0.0, kLine};
  ctx.unknown_area.extend(Vec3(-0.08, -0.06, 0.0));
  ctx.unknown_area.extend(Vec3(0.08, 0.06, 0.16));
  const auto set = nbs::SphereSearch{}.generate(ctx);
  REQUIRE(set.status == nbs::CandidateStatus::ok);
  REQUIRE(set.candidates.size() == 81);
  const double d_s = 0.3, radius = d_s + 0.08;  // d_s = middle of 0.15-0.45; half the largest extent 0.16
  for (std::size_t k = 0; k < set.candidates.size(); ++k) {
    const auto& c = set.candidates[k];
    CHECK(c.source == nbs::CandidateSource::sphere);
    CHECK(c.index == k);
    check_pose_and_aim(c, d_s);
    CHECK(c.path.length() == Approx(0.30).margin(1e-12));
    // The middle of the path is on the sphere around the box centre and looks at it.
    const Vec3 mid = 0.5 * (c.path.start().position() + c.path.end_position());
    CHECK((mid - Vec3(0, 0, 0.08)).norm() == Approx(radius).margin(1e-9));
    CHECK(c.path.start().view_direction().dot((Vec3(0, 0, 0.08) - mid).normalized()) == Approx(1.0).margin(1e-12));
  }
  SECTION("empty unknown area: clear status, no candidate") {
    ctx.unknown_area = nbs::Aabb{};
    const auto e = nbs::SphereSearch{}.generate(ctx);
    CHECK(e.status == nbs::CandidateStatus::empty_unknown_area);
    CHECK(e.candidates.empty());
  }
}

TEST_CASE("bad input: empty mesh gives a status, invalid parameters throw InvalidArgument", "[generators]") {
  nbs::Parameters params;
  nbs::StreamingMesh empty{params};
  const Space space(0.005);
  const Context ctx{empty, space, params, nbs::Pose::Identity(), 0.0, kLine};
  for (const auto& set : {nbs::BoundarySearch{}.generate(ctx), nbs::HoleRescan{}.generate(ctx)}) {
    CHECK(set.status == nbs::CandidateStatus::empty_mesh);
    CHECK(set.candidates.empty());
    CHECK(nbs::to_string(set.status) == "empty mesh: no triangle yet");
  }

  PlaneScan scan;
  SECTION("a new scan without points: no boundary in M_cur") {
    scan.mesh.begin_scan(scan.mesh.current_sensor());
    const auto set = nbs::BoundarySearch{}.generate(scan.context());
    CHECK(set.status == nbs::CandidateStatus::no_boundaries);
    CHECK(set.candidates.empty());
  }
  SECTION("hole limits that exclude every hole") {
    scan.params.hole_min_edges = 190;
    scan.params.hole_max_edges = 191;
    CHECK(nbs::HoleRescan{}.generate(scan.context()).status == nbs::CandidateStatus::no_holes);
  }
  SECTION("invalid parameters") {
    scan.params.scan_overlap = 1.5;
    CHECK_THROWS_AS(nbs::BoundarySearch{}.generate(scan.context()), nbs::InvalidArgument);
    CHECK_THROWS_AS(nbs::HoleRescan{}.generate(scan.context()), nbs::InvalidArgument);
  }
  SECTION("d_s outside the working range, bad pose, bad sensor, bad setting") {
    auto ctx2 = scan.context();
    ctx2.standoff_m = 0.6;
    CHECK_THROWS_AS(nbs::BoundarySearch{}.generate(ctx2), nbs::InvalidArgument);
    ctx2.standoff_m = std::numeric_limits<double>::quiet_NaN();
    CHECK_THROWS_AS(nbs::SphereSearch{}.generate(ctx2), nbs::InvalidArgument);
    auto ctx3 = scan.context();
    ctx3.last_sensor.linear()(0, 0) = 2.0;
    CHECK_THROWS_AS(nbs::BoundarySearch{}.generate(ctx3), nbs::InvalidArgument);
    auto g = kLine;
    g.fov_x_rad = 0.0;
    CHECK_THROWS_AS(nbs::BoundarySearch{}.generate(scan.context(g)), nbs::InvalidArgument);
    nbs::BoundarySearch::Setting bad;
    bad.region_fraction = 0.0;
    CHECK_THROWS_AS(nbs::BoundarySearch{bad}, nbs::InvalidArgument);
    nbs::HoleRescan::Setting bad_hr;
    bad_hr.selection_fraction = -0.1;
    CHECK_THROWS_AS(nbs::HoleRescan{bad_hr}, nbs::InvalidArgument);
  }
}

TEST_CASE("area sensor: single viewpoints; generators are deterministic", "[generators]") {
  PlaneScan scan;
  const nbs::SensorGeometry area{nbs::SensorGeometry::Kind::area, {0.15, 0.45}, 0.6, 0.45};
  const auto a = nbs::BoundarySearch{}.generate(scan.context(area));
  REQUIRE(a.status == nbs::CandidateStatus::ok);
  for (const auto& c : a.candidates) {
    CHECK(c.path.length() == 0.0);
    check_pose_and_aim(c, 0.3);
  }
  const auto l1 = nbs::BoundarySearch{}.generate(scan.context()), l2 = nbs::BoundarySearch{}.generate(scan.context());
  REQUIRE(l1.candidates.size() == l2.candidates.size());
  for (std::size_t i = 0; i < l1.candidates.size(); ++i) {
    CHECK(l1.candidates[i].path.start().pose().matrix() == l2.candidates[i].path.start().pose().matrix());
    CHECK(l1.candidates[i].path.end_position() == l2.candidates[i].path.end_position());
    CHECK(l1.candidates[i].path.length() > 0.0);
  }
}

TEST_CASE("boundary search: 1, 2 and 3 threads give the same candidates in the same order", "[generators]") {
  PlaneScan scan;
  const auto one = nbs::BoundarySearch{}.generate(scan.context());
  REQUIRE(one.status == nbs::CandidateStatus::ok);
  REQUIRE(one.candidates.size() >= 2);  // several boundaries, so the threads share the work
  for (const unsigned t : {2u, 3u}) {
    Context ctx = scan.context();
    ctx.threads = t;
    const auto r = nbs::BoundarySearch{}.generate(ctx);
    CAPTURE(t);
    CHECK(r.status == one.status);
    CHECK(r.considered == one.considered);
    CHECK(r.rejected == one.rejected);
    REQUIRE(r.candidates.size() == one.candidates.size());
    for (std::size_t i = 0; i < r.candidates.size(); ++i) {
      const auto &a = r.candidates[i], &b = one.candidates[i];
      CHECK(a.index == b.index);
      CHECK(a.path.start().pose().matrix() == b.path.start().pose().matrix());
      CHECK(a.path.end_position() == b.path.end_position());
      CHECK(a.targets.size() == b.targets.size());
      CHECK(a.sharp_corner == b.sharp_corner);
    }
  }
  Context bad = scan.context();
  bad.threads = 0;
  CHECK_THROWS_WITH(nbs::BoundarySearch{}.generate(bad), nbs_test::Contains("PlanningContext.threads") && nbs_test::Contains("0"));
}

TEST_CASE("planarity of normals (Eqs. 4.19-4.21 as the text reads them)", "[generators]") {
  // Plane: λ = (1, 0, 0). Cylinder normals over ±60 deg in one plane: the second-moment matrix has
  // λ2 = mean sin² = 1/2 − sin(2·60°)/(4·60° in rad) = 0.2933 > 0.09 -> not planar (with the mean-free C_N of
  // Eq. 4.20 λ2 = λ3 = 0 and a cylinder would count as planar).
  std::vector<Vec3> plane(50, Vec3(0, 0, 1)), cylinder;
  const int n = 2001;
  for (int i = 0; i < n; ++i) {
    const double a = -M_PI / 3 + (2 * M_PI / 3) * i / (n - 1);
    cylinder.emplace_back(std::sin(a), 0.0, std::cos(a));
  }
  const Vec3 lp = nbs::detail::normal_eigenvalues(plane), lc = nbs::detail::normal_eigenvalues(cylinder);
  CHECK(lp[0] == Approx(1.0).margin(1e-12));
  CHECK(lp[1] == Approx(0.0).margin(1e-12));
  CHECK(nbs::detail::normals_planar(plane, 0.09));
  CHECK(lc[1] == Approx(0.5 - std::sin(2 * M_PI / 3) / (4 * M_PI / 3)).epsilon(1e-3));
  CHECK(lc[2] == Approx(0.0).margin(1e-12));
  CHECK_FALSE(nbs::detail::normals_planar(cylinder, 0.09));
  CHECK_FALSE(nbs::detail::normals_planar({}, 0.09));
}

TEST_CASE("SEE generator: views above a scanned strip look down and sweep outward; deterministic", "[generators][see]") {
  const PlaneScan strip;
  REQUIRE(strip.mesh.face_count() > 100);
  const nbs::SurfaceEdgeExplorer see;
  Context ctx = strip.context();
  ctx.unknown_area = nbs::Aabb{Vec3(-0.1, -0.1, -0.01), Vec3(0.1, 0.1, 0.05)};  // support plane 1 cm below
  const nbs::CandidateSet set = see.generate(ctx);
  REQUIRE(set.status == nbs::CandidateStatus::ok);
  REQUIRE(set.candidates.size() >= 4);  // a ≈ 6 × 7.6 cm strip: frontier all around, views 1 cm apart
  Vec3 centre = Vec3::Zero();
  for (nbs::VertexId v = 0; v < strip.mesh.vertex_count(); ++v) centre += strip.mesh.position(v);
  centre /= double(strip.mesh.vertex_count());
  const double d_s = ctx.standoff(), l_b = ctx.sensor.baseline_m(d_s);
  for (const nbs::ScanCandidate& c : set.candidates) {
    const nbs::Pose& t = c.path.start().pose();
    CHECK(t.linear().col(2).z() < -0.95);                         // looking down at the plane z = 0
    CHECK(std::abs(c.aim.point.z()) < 1e-3);                      // the frontier point lies on it
    CHECK(c.path.length() == Approx(l_b).epsilon(1e-9));           // l_b(d_s) by default
    Vec3 outward = c.aim.point - centre;
    outward.z() = 0.0;
    CHECK(t.linear().col(1).dot(outward.normalized()) > 0.3);     // the sweep leaves the observed strip
    CHECK(outward.norm() > 0.02);                                 // frontier points are near the strip's border
  }
  // Deterministic, and the same for any thread count.
  Context two = ctx;
  two.threads = 2;
  const nbs::CandidateSet twice = see.generate(two);
  REQUIRE(twice.candidates.size() == set.candidates.size());
  for (std::size_t i = 0; i < set.candidates.size(); ++i) {
    CHECK(twice.candidates[i].path.start().pose().matrix() == set.candidates[i].path.start().pose().matrix());
    CHECK(twice.candidates[i].path.end_position() == set.candidates[i].path.end_position());
  }
  // The view that repeats the last scan's start pose is not proposed again.
  nbs::SurfaceEdgeSetting s;
  s.repeat_distance_m = 1.0;
  s.repeat_angle_rad = M_PI;
  Context again = ctx;
  again.last_sensor = set.candidates.front().path.start().pose();
  CHECK(nbs::SurfaceEdgeExplorer(s).generate(again).status == nbs::CandidateStatus::all_rejected);
}
