// EdgeMesh conformance: StreamingMesh (thesis and noise-robust settings, after one and after two scans) and a
// minimal user-written edge mesh over an IndexedMesh.
#include "edge_mesh_conformance.hpp"

#include <map>

#include "../embree/analytic_meshes.hpp"
#include "../mesh/mesh_test_util.hpp"
#include "nbs/mesh/indexed_mesh.hpp"

namespace {

using nbs::MeshEdge;
using nbs::MeshFace;
using nbs::VertexId;
using nbs::Vec3;

/// The user-written edge mesh: an IndexedMesh (consistently oriented, manifold edges) with a directed-edge map.
class IndexedEdgeMesh {
public:
  explicit IndexedEdgeMesh(nbs::IndexedMesh m) : m_(std::move(m)) {
    for (const auto& t : m_.triangles)
      for (int k = 0; k < 3; ++k) left_[{t[k], t[(k + 1) % 3]}] = t[(k + 2) % 3];
  }
  [[nodiscard]] std::size_t vertex_count() const { return m_.vertices.size(); }
  [[nodiscard]] Vec3 position(VertexId v) const { return m_.vertices[v]; }
  [[nodiscard]] Vec3 normal(VertexId) const { return Vec3::UnitZ(); }  // a plane facing +z
  [[nodiscard]] std::size_t face_count() const { return m_.triangles.size(); }
  [[nodiscard]] VertexId left_vertex(VertexId a, VertexId b) const {
    const auto it = left_.find({a, b});
    return it == left_.end() ? nbs::kNoVertex : it->second;
  }
  template <class F>
  void for_each_edge(F&& f) const {
    for (const auto& [e, l] : left_)
      if (e.first < e.second || left_vertex(e.second, e.first) == nbs::kNoVertex) {
        const VertexId a = std::min(e.first, e.second), b = std::max(e.first, e.second);
        f(MeshEdge{a, b, left_vertex(a, b), left_vertex(b, a)});
      }
  }
  template <class F>
  void for_each_face(F&& f) const {
    for (const auto& t : m_.triangles) f(MeshFace{t[0], t[1], t[2]});
  }

private:
  nbs::IndexedMesh m_;
  std::map<std::pair<VertexId, VertexId>, VertexId> left_;
};

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
