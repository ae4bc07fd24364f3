// SPDX-License-Identifier: BSD-3-Clause
// CandidateGenerator conformance: BoundarySearch, HoleRescan, SphereSearch, SurfaceEdgeExplorer (SEE) and a minimal user-written generator, on
// a scanned plane with a hole (line and area sensor), an empty mesh and an empty unknown area.
#include "candidate_generator_conformance.hpp"

#include "../mesh/mesh_test_util.hpp"
#include "nbs/candidates/generators.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"

namespace {

using nbs::Vec3;
using Space = nbs::ProbabilisticVoxelSpace<>;
using Context = nbs::PlanningContext<nbs::StreamingMesh, Space>;

/// The user-written generator: one single-viewpoint candidate looking straight down at the unknown area's centre.
struct LookDown {
  [[nodiscard]] nbs::CandidateSet generate(const Context& ctx) const {
    ctx.validate();
    nbs::CandidateSet out;
    if (ctx.unknown_area.empty()) {
      out.status = nbs::CandidateStatus::empty_unknown_area;
      return out;
    }
    const Vec3 aim = ctx.unknown_area.center();
    nbs::ScanCandidate c;
    c.source = nbs::CandidateSource::sphere;
    c.path = nbs::LinearScanPath(
        nbs::Viewpoint::from_axes(Vec3(1, 0, 0), Vec3(0, -1, 0), Vec3(0, 0, -1), aim + Vec3(0, 0, ctx.standoff())));
    c.aim.point = aim;
    out.candidates.push_back(c);
    out.considered = 1;
    return out;
  }
};

const nbs::SensorGeometry kLine{nbs::SensorGeometry::Kind::line, {0.15, 0.45}, 0.5, 0.0};
const nbs::SensorGeometry kArea{nbs::SensorGeometry::Kind::area, {0.15, 0.45}, 0.6, 0.45};

struct Scene {
  nbs::Parameters params;
  nbs::StreamingMesh mesh{params};
  nbs::StreamingMesh empty{params};
  Space space{0.005};
  Scene() {
    nbs::test::PlanePatch plane(0.2, 0.2);
    plane.holes.push_back(Eigen::Vector3d(0.0, 0.01, 0.012));
    nbs::test::StripeSensor s;
    s.rays = 160;
    s.step_m = 0.0005;
    const nbs::Scan scan = nbs::test::scan_path(plane, nbs::test::down_at(0, 0.03, 0.15), 0.06, s, 5);
    mesh.integrate(scan);
    (void)space.integrate(scan);
  }
  [[nodiscard]] std::vector<Context> contexts() const {
    const nbs::Aabb box{Vec3(-0.08, -0.06, -0.01), Vec3(0.08, 0.06, 0.05)};
    std::vector<Context> out;
    for (const auto& g : {kLine, kArea}) {
      out.push_back(Context{mesh, space, params, mesh.current_sensor(), 0.06, g, box});
      out.push_back(Context{mesh, space, params, mesh.current_sensor(), 0.06, g, nbs::Aabb{}});
      out.push_back(Context{empty, space, params, nbs::Pose::Identity(), 0.0, g, box, 0.25, 2});
    }
    return out;
  }
};

}  // namespace

TEST_CASE("CandidateGenerator conformance: every model and a user-written one", "[conformance][generators]") {
  using nbs::conformance::check_candidate_generator_conformance;
  const Scene scene;
  REQUIRE(scene.mesh.face_count() > 100);
  const auto ctxs = scene.contexts();
  CHECK(check_candidate_generator_conformance(nbs::BoundarySearch{}, ctxs) > 0);
  CHECK(check_candidate_generator_conformance(nbs::HoleRescan{}, ctxs) > 0);
  CHECK(check_candidate_generator_conformance(nbs::SphereSearch{}, ctxs, false) > 0);  // see the next test case
  CHECK(check_candidate_generator_conformance(LookDown{}, ctxs) > 0);
  CHECK(check_candidate_generator_conformance(nbs::SurfaceEdgeExplorer{}, ctxs) > 0);
  // The empty cases come with their status.
  CHECK(nbs::BoundarySearch{}.generate(ctxs[2]).status == nbs::CandidateStatus::empty_mesh);
  CHECK(nbs::HoleRescan{}.generate(ctxs[2]).status == nbs::CandidateStatus::empty_mesh);
  CHECK(nbs::SurfaceEdgeExplorer{}.generate(ctxs[2]).status == nbs::CandidateStatus::empty_mesh);
  CHECK(nbs::SphereSearch{}.generate(ctxs[1]).status == nbs::CandidateStatus::empty_unknown_area);
  CHECK(LookDown{}.generate(ctxs[1]).status == nbs::CandidateStatus::empty_unknown_area);
}

// Known deviation, kept visible: ScanCandidate documents "zero length for area sensors", but SphereSearch returns
// its 0.30 m sphere paths (sphere_path_length_m) for an area sensor too; an area-sensor scanner then images only the
// path's start, which is not the viewpoint on the sphere (the path's middle is). Remove [!mayfail] once fixed.
TEST_CASE("CandidateGenerator conformance: SphereSearch with an area sensor gives single viewpoints",
          "[conformance][generators][!mayfail]") {
  const Scene scene;
  const auto ctxs = scene.contexts();
  const std::vector<Context> area{ctxs[3]};
  CHECK(nbs::conformance::check_candidate_generator_conformance(nbs::SphereSearch{}, area) > 0);
}
