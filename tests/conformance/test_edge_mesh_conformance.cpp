// SPDX-License-Identifier: BSD-3-Clause
// EdgeMesh conformance: StreamingMesh (thesis and noise-robust settings, after one and after two scans) and a
// minimal user-written edge mesh over an IndexedMesh.
#include "edge_mesh_conformance.hpp"

#include <map>

#include "../embree/analytic_meshes.hpp"
#include "../mesh/mesh_test_util.hpp"
#include "indexed_edge_mesh.hpp"
#include "nbs/mesh/indexed_mesh.hpp"

namespace {

using nbs::conformance::IndexedEdgeMesh;
using nbs::MeshEdge;
using nbs::MeshFace;
using nbs::VertexId;
using nbs::Vec3;

}  // namespace

TEST_CASE("EdgeMesh conformance: a user-written edge mesh over an IndexedMesh", "[conformance][mesh]") {
  static_assert(nbs::EdgeMesh<IndexedEdgeMesh> && !nbs::KnowsFaceBorders<IndexedEdgeMesh>);
  const IndexedEdgeMesh plane(nbs_test::plane_mesh(0.05, 0.0, 4));
  nbs::conformance::check_edge_mesh_conformance(plane);
  std::size_t borders = 0;
  plane.for_each_edge([&](const MeshEdge& e) { borders += e.is_border() ? 1 : 0; });
  CHECK(borders == 16);  // the rim of a 4 × 4 grid
}

TEST_CASE("EdgeMesh conformance: StreamingMesh", "[conformance][mesh]") {
  static_assert(nbs::KnowsFaceBorders<nbs::StreamingMesh> && nbs::ListsCurrentFaces<nbs::StreamingMesh>);
  nbs::Parameters params;
  nbs::test::PlanePatch plane(0.2, 0.2);
  plane.holes.push_back(Eigen::Vector3d(0.0, 0.01, 0.006));
  nbs::test::StripeSensor s;
  s.rays = 160;
  s.step_m = 0.0005;
  for (const bool robust : {false, true}) {
    INFO("noise-robust settings " << robust);
    nbs::StreamingMeshSettings ms = nbs::StreamingMeshSettings::from(params);
    ms.project_vertices = false;
    ms.density_depth_m = 0.0;
    if (robust) {
      ms.project_vertices = true;
      ms.density_depth_m = ms.normal_radius_m;
    }
    nbs::StreamingMesh mesh(ms);
    (void)mesh.integrate(nbs::test::scan_path(plane, nbs::test::down_at(0, 0.03, 0.15), 0.06, s, 5));
    REQUIRE(mesh.face_count() > 100);
    // Normals are weighted-PCA estimates on noisy points: a few faces (3 of ~1000 here) are clockwise around them.
    nbs::conformance::check_edge_mesh_conformance(mesh, 0.01);
    (void)mesh.integrate(nbs::test::scan_path(plane, nbs::test::down_at(0.03, 0.02, 0.15), 0.05, s, 6));
    nbs::conformance::check_edge_mesh_conformance(mesh, 0.01);
  }
}
