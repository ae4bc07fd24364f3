// SPDX-License-Identifier: BSD-3-Clause
// Hole Rescan (Sec. 4.4, Alg. 2, Eqs. 4.22-4.23): the 20 % rule by hand, the direction pattern, a hole under an
// occupied overhang (analytic free set), path geometry and combined paths.
#include "nbs_catch.hpp"

#include <cmath>

#include "nbs/space/probabilistic_voxel_space.hpp"
#include "../mesh/mesh_test_util.hpp"
#include "nbs/candidates/hole_rescan.hpp"

using nbs::Vec3;

namespace {

using Space = nbs::ProbabilisticVoxelSpace<>;
using Context = nbs::PlanningContext<nbs::StreamingMesh, Space>;
constexpr double kDs = 0.3;

struct HolePlane {
  nbs::Parameters params;
  nbs::StreamingMesh mesh{params};
  HolePlane(const std::vector<Eigen::Vector3d>& holes) {
    params.hole_min_edges = 8;  // ignore the 3-4 edge triangulation gaps along the strip border
    nbs::test::PlanePatch plane(0.04, 0.04);
    plane.holes = holes;
    nbs::test::StripeSensor s;
    s.rays = 160;
    s.step_m = 0.0005;
    mesh.integrate(nbs::test::scan_path(plane, nbs::test::down_at(0, 0.045, 0.15), 0.09, s, 3));
  }
  [[nodiscard]] Context context(const Space& space) const {
    return Context{mesh, space, params, mesh.current_sensor(), 0.09,
                   {nbs::SensorGeometry::Kind::line, {0.1, 0.5}, 0.5, 0.0}, {}, kDs};
  }
  [[nodiscard]] const nbs::Hole& nearest_hole(const Vec3& c) const {
    static std::vector<nbs::Hole> holes;
    holes = nbs::find_holes(mesh, params);
    REQUIRE_FALSE(holes.empty());
    std::size_t best = 0;
    for (std::size_t i = 1; i < holes.size(); ++i)
      if ((holes[i].center - c).norm() < (holes[best].center - c).norm()) best = i;
    return holes[best];
  }
};

// Occupied slab z in [0.05, 0.055), x < 0.025, |y| < 0.3 (5 mm voxels): one end point per voxel, beams from above.
Space overhang_space() {
  Space space(0.005);
  nbs::Scan scan;
  for (double x = -0.2975; x < 0.025; x += 0.005)
    for (double y = -0.2975; y < 0.3; y += 0.005) {
      scan.profile_poses.push_back(nbs::test::down_at(x, y, 0.1).pose());
      scan.add_point(Vec3(x, y, 0.0525), static_cast<std::uint32_t>(scan.profile_poses.size() - 1));
    }
  (void)space.integrate(scan);
  return space;
}

// Analytic free test of a direction from c for the slab above (the first offset metres skipped).
bool slab_free(const Vec3& c, const Vec3& n) {
  if (n.z() <= 0.0) return true;
  for (double z : {0.05, 0.055}) {
    const Vec3 p = c + (z - c.z()) / n.z() * n;
    if (p.x() < 0.025 && std::abs(p.y()) < 0.3 && (p - c).norm() <= kDs) return false;
  }
  return true;
}

}  // namespace

TEST_CASE("Alg. 2 selection: the free sample at 20 % of the distance range to the PCA normal", "[hr]") {
  // Samples at 0..50 deg from n_h = z; d_n = 2 sin(θ/2). Free: 20..50 deg. Key = d(20) + 0.2 (d(50) − d(20))
  // = 0.3473 + 0.2 · 0.4979 = 0.4469 -> lower_bound picks 30 deg (d = 0.5176), sample 3.
  std::vector<Vec3> samples;
  for (int k = 0; k <= 5; ++k) {
    const double a = k * 10.0 * M_PI / 180.0;
    samples.emplace_back(std::sin(a), 0.0, std::cos(a));
  }
  const std::vector<char> free{0, 0, 1, 1, 1, 1};
  const auto pick = nbs::detail::select_hole_normal(Vec3::UnitZ(), samples, free);
  REQUIRE(pick);
  CHECK(*pick == 3);
  CHECK(nbs::detail::select_hole_normal(Vec3::UnitZ(), samples, {1, 1, 1, 1, 1, 1}) == std::optional<std::size_t>(1));
  CHECK_FALSE(nbs::detail::select_hole_normal(Vec3::UnitZ(), samples, std::vector<char>(6, 0)));
}

TEST_CASE("direction pattern: fixed, unit, on the requested hemisphere", "[hr]") {
  const Vec3 pole = Vec3(1, 2, 3).normalized();
  const auto a = nbs::detail::spiral_directions(pole, 200, true), b = nbs::detail::spiral_directions(pole, 200, true);
  REQUIRE(a.size() == 200);
  Vec3 mean = Vec3::Zero();
  for (std::size_t i = 0; i < a.size(); ++i) {
    CHECK(a[i] == b[i]);
    CHECK(a[i].norm() == Approx(1.0).margin(1e-12));
    CHECK(a[i].dot(pole) > 0.0);
    mean += a[i] / 200.0;
  }
  CHECK((mean - 0.5 * pole).norm() < 0.02);  // uniform on the hemisphere: E[ñ] = pole / 2
  const auto full = nbs::detail::spiral_directions(pole, 200, false);
  Vec3 m2 = Vec3::Zero();
  for (const Vec3& d : full) m2 += d / 200.0;
  CHECK(m2.norm() < 0.02);
}

TEST_CASE("Hole Rescan finds an occlusion-free direction for a hole under an overhang (Alg. 2)", "[hr]") {
  HolePlane scene({Eigen::Vector3d(0, 0, 0.008)});
  const Space space = overhang_space();
  REQUIRE(space.occupied(*space.grid().key_of(Vec3(0.0, 0.0, 0.0525))));
  REQUIRE_FALSE(space.occupied(*space.grid().key_of(Vec3(0.03, 0.0, 0.0525))));
  const nbs::Hole& hole = scene.nearest_hole(Vec3::Zero());
  REQUIRE(hole.center.norm() < 0.002);
  REQUIRE(hole.normal.z() > 0.99);
  const double offset = 2.0 * space.resolution_m();
  // The PCA normal itself is occluded by the overhang.
  CHECK_FALSE(nbs::detail::occlusion_free(space, hole.center, hole.normal, kDs, offset));

  const nbs::HoleRescan hr;
  const auto n = hr.hole_direction(space, hole, 200, kDs, offset);
  REQUIRE(n);
  CHECK(slab_free(hole.center, *n));
  // Oracle: the same pattern and the 20 % rule on the analytic free set.
  const auto dirs = nbs::detail::spiral_directions(hole.normal.normalized(), 200, true);
  std::vector<char> free;
  for (const Vec3& d : dirs) free.push_back(slab_free(hole.center, d));
  const auto expected = nbs::detail::select_hole_normal(hole.normal.normalized(), dirs, free);
  REQUIRE(expected);
  INFO("chosen " << n->transpose() << " analytic " << dirs[*expected].transpose());
  CHECK(std::acos(std::clamp(n->dot(dirs[*expected]), -1.0, 1.0)) < 8.0 * M_PI / 180.0);
  CHECK(std::atan2(n->head<2>().norm(), n->z()) > std::atan(0.025 / 0.05) - 1e-9);  // past the overhang edge

  SECTION("the candidate: Eqs. 4.22-4.23 along the chosen direction") {
    const auto set = hr.generate(scene.context(space));
    REQUIRE(set.status == nbs::CandidateStatus::ok);
    const nbs::ScanCandidate* c = nullptr;
    for (const auto& x : set.candidates)
      if ((x.aim.point - hole.center).norm() < 1e-12) c = &x;
    REQUIRE(c != nullptr);
    REQUIRE(c->merged.size() == 1);
    const Vec3 nh = c->aim.normal;
    CHECK(nh.isApprox(*n, 1e-12));
    const nbs::Viewpoint& v = c->path.start();
    CHECK(v.view_direction().isApprox(-nh, 1e-12));
    const Vec3 d = hole.largest_direction - hole.largest_direction.dot(nh) * nh;
    const Vec3 e1 = hole.center - 1.1 * d + kDs * nh, e2 = hole.center + 1.1 * d + kDs * nh;
    const Vec3 p1 = v.position(), p2 = c->path.end_position();
    CHECK(std::min((p1 - e1).norm() + (p2 - e2).norm(), (p1 - e2).norm() + (p2 - e1).norm()) < 1e-9);
    CHECK((p2 - p1).cross(v.y_axis()).norm() < 1e-9);
    CHECK((v.pose().linear().transpose() * v.pose().linear() - nbs::Mat3::Identity()).cwiseAbs().maxCoeff() < 1e-9);
    CHECK((c->aim.point - v.position()).dot(v.view_direction()) == Approx(kDs).margin(1e-9));
    CHECK(c->targets.size() == 5);
  }
}

TEST_CASE("Hole Rescan combines holes of similar centre and orientation into one path", "[hr]") {
  HolePlane scene({Eigen::Vector3d(-0.007, 0, 0.004), Eigen::Vector3d(0.007, 0, 0.004),
                   Eigen::Vector3d(0.0, -0.028, 0.004)});
  const Space empty(0.005);
  const auto set = nbs::HoleRescan{}.generate(scene.context(empty));
  REQUIRE(set.status == nbs::CandidateStatus::ok);
  const auto holes = nbs::find_holes(scene.mesh, scene.params);
  auto nearest = [&](const Vec3& c) {
    std::size_t best = 0;
    for (std::size_t i = 1; i < holes.size(); ++i)
      if ((holes[i].center - c).norm() < (holes[best].center - c).norm()) best = i;
    return best;
  };
  const std::size_t a = nearest(Vec3(-0.007, 0, 0)), b = nearest(Vec3(0.007, 0, 0)), far = nearest(Vec3(0, -0.028, 0));
  REQUIRE((holes[a].center - Vec3(-0.007, 0, 0)).norm() < 0.002);
  REQUIRE((holes[b].center - Vec3(0.007, 0, 0)).norm() < 0.002);
  int with_a = 0;
  for (const auto& c : set.candidates) {
    const auto has = [&](std::size_t i) { return std::find(c.merged.begin(), c.merged.end(), i) != c.merged.end(); };
    if (!has(a)) continue;
    ++with_a;
    CHECK(has(b));
    CHECK_FALSE(has(far));  // 28 mm away: more than merge_distance_m = 20 mm
    // The path sweeps across both holes along x: the feet of its ends (minus d_s n_h) lie beyond both centres
    // (the rims c ± d_h extend it further only as far as d_h points along x).
    const Vec3 back = kDs * c.aim.normal;
    const double x1 = (c.path.start().position() - back).x(), x2 = (c.path.end_position() - back).x();
    CHECK(std::min(x1, x2) < holes[a].center.x());
    CHECK(std::max(x1, x2) > holes[b].center.x());
    CHECK(std::abs(c.path.start().y_axis().x()) > 0.9);
  }
  CHECK(with_a == 1);
}

TEST_CASE("Hole Rescan skips holes whose surface was measured (a triangulation gap, not unseen surface)", "[hr]") {
  HolePlane scene({Eigen::Vector3d(0, 0, 0.004), Eigen::Vector3d(0.0, -0.028, 0.004)});
  // Voxel space with the eight 5 mm voxels around the origin occupied (surface measured at the first hole only).
  Space space(0.005);
  nbs::Scan scan;
  for (double x : {-0.0025, 0.0025})
    for (double y : {-0.0025, 0.0025})
      for (double z : {-0.0025, 0.0025}) {
        scan.profile_poses.push_back(nbs::test::down_at(x, y, 0.1).pose());
        scan.add_point(Vec3(x, y, z), static_cast<std::uint32_t>(scan.profile_poses.size() - 1));
      }
  (void)space.integrate(scan);
  REQUIRE(space.occupied(*space.grid().key_of(Vec3(0.001, 0.001, 0.001))));
  const auto holes = nbs::find_holes(scene.mesh, scene.params);
  auto aims_near = [](const nbs::CandidateSet& set, const Vec3& c) {
    int n = 0;
    for (const auto& x : set.candidates)
      if ((x.aim.point - c).norm() < 0.003) ++n;
    return n;
  };
  const nbs::HoleRescan hr;
  const auto set = hr.generate(scene.context(space));
  REQUIRE(set.status == nbs::CandidateStatus::ok);
  // Oracle: a hole is measured iff its centre lies within a voxel edge (along n_h) of one of the eight voxels.
  std::size_t expected_measured = 0;
  for (const auto& h : holes)
    expected_measured += (h.center.cwiseAbs().maxCoeff() < 0.005 + 1e-9 && std::abs(h.center.z()) < 0.005) ? 1 : 0;
  CHECK(expected_measured >= 1);
  CHECK(set.measured == expected_measured);
  CHECK(aims_near(set, Vec3(0, 0, 0)) == 0);
  CHECK(aims_near(set, Vec3(0, -0.028, 0)) == 1);
  // Switched off, or in an empty space, the hole at the origin gets its path.
  nbs::HoleRescanSetting off;
  off.skip_measured_holes = false;
  const auto all = nbs::HoleRescan(off).generate(scene.context(space));
  CHECK(all.measured == 0);
  CHECK(aims_near(all, Vec3(0, 0, 0)) == 1);
  const Space empty(0.005);
  const auto in_empty = hr.generate(scene.context(empty));
  CHECK(in_empty.measured == 0);
  CHECK(aims_near(in_empty, Vec3(0, 0, 0)) == 1);
  nbs::HoleRescanSetting bad;
  bad.measured_probe_voxels = -1.0;
  CHECK_THROWS_AS(nbs::HoleRescan{bad}, nbs::InvalidArgument);
}
