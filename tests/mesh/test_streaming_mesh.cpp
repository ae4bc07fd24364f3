#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "analytic_scanner.hpp"
#include "nbs/mesh/invariants.hpp"
#include "nbs/mesh/streaming_mesh.hpp"

using nbs::Vec3;

namespace {
nbs::Viewpoint down_at(double x, double y, double height) {
  return nbs::Viewpoint::from_axes(Vec3(1, 0, 0), Vec3(0, -1, 0), Vec3(0, 0, -1), Vec3(x, y, height));
}
}  // namespace

TEST_CASE("plane patch: invariants, normals", "[mesh]") {
  nbs::test::PlanePatch plane(0.03, 0.03);
  nbs::test::StripeSensor sensor;
  const auto scan = nbs::test::scan_path(plane, down_at(0, 0.04, 0.15), 0.08, sensor, 1);
  nbs::StreamingMesh mesh;
  mesh.integrate(scan);
  const auto& st = mesh.stats();
  WARN("received " << st.received << " stored " << st.stored << " meshed " << st.meshed << " faces "
                   << mesh.face_count() << " normal failures " << st.normal_failures);
  double area = 0;
  std::size_t border = 0, edges = 0, isolated = 0;
  mesh.for_each_face([&](const nbs::MeshFace& f) {
    area += 0.5 * (mesh.position(f.b) - mesh.position(f.a)).cross(mesh.position(f.c) - mesh.position(f.a)).norm();
  });
  mesh.for_each_edge([&](const nbs::MeshEdge& e) { ++edges; border += e.is_border(); });
  for (nbs::VertexId v = 0; v < mesh.vertex_count(); ++v) isolated += !mesh.in_triangle(v);
  WARN("area mm2 " << area * 1e6 << " edges " << edges << " border " << border << " isolated " << isolated);
  const auto rep = nbs::check_invariants(mesh, mesh.settings().reduction_radius_m);
  INFO(rep.problems);
  CHECK(rep.ok());
}
