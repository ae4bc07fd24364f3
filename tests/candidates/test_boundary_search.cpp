// SPDX-License-Identifier: BSD-3-Clause
// Boundary Search (Secs. 4.2.2-4.3.2) against analytic scans: planes, a box and a sphere.
#include "nbs_catch.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "nbs/space/probabilistic_voxel_space.hpp"
#include "../mesh/mesh_test_util.hpp"
#include "nbs/candidates/boundary_search.hpp"

using nbs::Vec3;

namespace {

using Space = nbs::ProbabilisticVoxelSpace<>;
using Context = nbs::PlanningContext<nbs::StreamingMesh, Space>;

nbs::SensorGeometry line_sensor(const nbs::test::StripeSensor& s) {
  return {nbs::SensorGeometry::Kind::line, {0.1, 0.5}, s.fov_rad, 0.0};
}

struct Scanned {
  nbs::Parameters params;
  nbs::StreamingMesh mesh{params};
  Space space{0.005};
  nbs::test::StripeSensor sensor;
  double length_m = 0.0;
  Scanned(const nbs::test::Shape& shape, const nbs::Viewpoint& start, double length) : length_m(length) {
    mesh.integrate(nbs::test::scan_path(shape, start, length, sensor, 7));
  }
  [[nodiscard]] Context context(double standoff = 0.3) const {
    return Context{mesh, space, params, mesh.current_sensor(), length_m, line_sensor(sensor), {}, standoff};
  }
};

// Every candidate: finite orthonormal right-handed pose, aim at d_s along s_z from the path line.
void check_candidate_geometry(const nbs::ScanCandidate& c, double d_s) {
  const nbs::Pose& s = c.path.start().pose();
  REQUIRE(s.matrix().allFinite());
  CHECK((s.linear().transpose() * s.linear() - nbs::Mat3::Identity()).cwiseAbs().maxCoeff() < 1e-9);
  CHECK(s.linear().determinant() == Approx(1.0).margin(1e-9));
  const Vec3 rel = c.aim.point - c.path.start().position();
  CHECK(rel.dot(c.path.start().view_direction()) == Approx(d_s).margin(1e-9));
  CHECK((rel - rel.dot(c.path.start().view_direction()) * c.path.start().view_direction())
            .cross(c.path.start().y_axis())
            .norm() < 1e-9);
  // The path moves along +s_y.
  const Vec3 move = c.path.end_position() - c.path.start().position();
  CHECK(move.cross(c.path.start().y_axis()).norm() < 1e-9);
  CHECK(move.dot(c.path.start().y_axis()) >= 0.0);
  for (const auto& t : c.targets) {
    CHECK(t.point.allFinite());
    CHECK(t.normal.norm() == Approx(1.0).margin(1e-9));
  }
}

}  // namespace

TEST_CASE("planar boundary: viewpoint perpendicular to the patch at d_s with overlap o (Eqs. 4.14-4.18)", "[bs]") {
  // A plane larger than the stripe: the left/right boundaries lie on the limiting rays, so no sharp-corner rotation.
  const double h = 0.15;
  nbs::test::PlanePatch plane(0.2, 0.2);
  Scanned s(plane, nbs::test::down_at(0, 0.04, h), 0.08);
  const double d_s = 0.3, half_fov = 0.5 * s.sensor.fov_rad;
  const double edge_x = h * std::tan(half_fov);  // analytic border of the scanned strip
  for (double o : {0.1, 0.3, 0.45}) {
    s.params.scan_overlap = o;
    const auto set = nbs::BoundarySearch{}.generate(s.context(d_s));
    REQUIRE(set.status == nbs::CandidateStatus::ok);
    int sides = 0;
    for (const auto& c : set.candidates) {
      check_candidate_geometry(c, d_s);
      CHECK_FALSE(c.sharp_corner);
      const nbs::Viewpoint& v = c.path.start();
      CHECK(v.view_direction().dot(Vec3(0, 0, -1)) > std::cos(0.5 * M_PI / 180.0));  // perpendicular to z = 0
      CHECK(c.aim.point.z() == Approx(0.0).margin(3e-4));                              // on the patch
      CHECK(v.position().z() == Approx(d_s).margin(3e-4));
      CHECK(c.overlap == Approx(o).margin(1e-6));
      const double l_b = 2.0 * d_s * std::tan(half_fov);
      if (std::abs(c.aim.point.x()) > 0.03) {  // left (+x) or right (−x) boundary
        ++sides;
        // Eq. 4.14 on the analytic strip: the FOV [x_p − l_b/2, x_p + l_b/2] overlaps [.., edge_x] by o·l_b.
        const double expected = edge_x + l_b * (0.5 - o);
        INFO("overlap " << o << " aim x " << c.aim.point.x());
        CHECK(std::abs(c.aim.point.x()) == Approx(expected).margin(1.5e-3));
        // Fig. 4.9: the path spans the mesh along the boundary, here the scanned y range [−0.04, 0.04].
        const double y0 = c.path.start().position().y(), y1 = c.path.end_position().y();
        CHECK(std::min(y0, y1) == Approx(-0.04).margin(1.5e-3));
        CHECK(std::max(y0, y1) == Approx(0.04).margin(1.5e-3));
      }
    }
    CHECK(sides == 2);
  }
}

TEST_CASE("sharp-corner rule triggers on a box edge and not on a sphere (Eqs. 4.19-4.21, Fig. 4.7)", "[bs]") {
  SECTION("box: planar top face, edges inside the FOV -> rotated 45 deg about the boundary") {
    nbs::test::Box box(Vec3(-0.03, -0.03, -0.06), Vec3(0.03, 0.03, 0.0));
    Scanned s(box, nbs::test::down_at(0, 0.06, 0.15), 0.12);
    const auto set = nbs::BoundarySearch{}.generate(s.context());
    REQUIRE(set.status == nbs::CandidateStatus::ok);
    REQUIRE(set.candidates.size() == 4);
    for (const auto& c : set.candidates) {
      check_candidate_geometry(c, 0.3);
      CHECK(c.sharp_corner);
      // The side face beyond the boundary: its outward normal is the horizontal direction towards the aim.
      const Vec3 side = Vec3(c.aim.point.x(), c.aim.point.y(), 0).cwiseProduct(
          (Vec3(c.aim.point.x(), c.aim.point.y(), 0).cwiseAbs().array() > 0.03).cast<double>().matrix());
      REQUIRE(side.norm() > 0.0);
      const Vec3 s_z = c.path.start().view_direction();
      INFO("s_z " << s_z.transpose());
      CHECK(s_z.dot(side.normalized()) == Approx(-std::sqrt(0.5)).margin(0.03));
      CHECK(s_z.dot(Vec3(0, 0, -1)) == Approx(std::sqrt(0.5)).margin(0.03));
    }
  }
  SECTION("sphere: curved boundary region -> no rotation") {
    nbs::test::Sphere sphere(Vec3(0, 0, 0), 0.04);
    Scanned s(sphere, nbs::test::down_at(0, 0.07, 0.2), 0.14);
    const auto set = nbs::BoundarySearch{}.generate(s.context());
    REQUIRE(set.status == nbs::CandidateStatus::ok);
    REQUIRE_FALSE(set.candidates.empty());
    for (const auto& c : set.candidates) {
      check_candidate_geometry(c, 0.3);
      CHECK_FALSE(c.sharp_corner);
    }
  }
}

namespace {

// A StreamingMesh seen only through the EdgeMesh members (no KnowsFaceBorders): mesh_topology takes for_each_edge.
struct PlainEdgeMesh {
  const nbs::StreamingMesh* m;
  [[nodiscard]] std::size_t vertex_count() const { return m->vertex_count(); }
  [[nodiscard]] Vec3 position(nbs::VertexId v) const { return m->position(v); }
  [[nodiscard]] Vec3 normal(nbs::VertexId v) const { return m->normal(v); }
  [[nodiscard]] std::size_t face_count() const { return m->face_count(); }
  [[nodiscard]] nbs::VertexId left_vertex(nbs::VertexId a, nbs::VertexId b) const { return m->left_vertex(a, b); }
  template <class F>
  void for_each_edge(F&& f) const { m->for_each_edge(f); }
  template <class F>
  void for_each_face(F&& f) const { m->for_each_face(f); }
};

}  // namespace

TEST_CASE("mesh topology from face borders equals the one from for_each_edge", "[bs]") {
  static_assert(nbs::EdgeMesh<PlainEdgeMesh> && !nbs::KnowsFaceBorders<PlainEdgeMesh>);
  nbs::test::Sphere sphere(Vec3(0, 0, 0), 0.04);
  Scanned s(sphere, nbs::test::down_at(0, 0.07, 0.2), 0.14);
  REQUIRE(s.mesh.face_count() > 100);
  const nbs::detail::MeshTopology fast = nbs::detail::mesh_topology(s.mesh);
  const nbs::detail::MeshTopology slow = nbs::detail::mesh_topology(PlainEdgeMesh{&s.mesh});
  CHECK(fast.offset == slow.offset);
  CHECK(fast.neighbours == slow.neighbours);
  CHECK(fast.triangulated == slow.triangulated);
}

TEST_CASE("region weights (Eq. 4.11) equal the brute-force nearest boundary vertex, bit for bit", "[bs]") {
  nbs::test::Sphere sphere(Vec3(0, 0, 0), 0.04);
  Scanned s(sphere, nbs::test::down_at(0, 0.07, 0.2), 0.14);
  const auto n = static_cast<nbs::VertexId>(s.mesh.vertex_count());
  REQUIRE(n > 100);
  std::vector<nbs::VertexId> region, boundary;
  for (nbs::VertexId v = 0; v < n; ++v) (v % 7 == 3 ? boundary : region).push_back(v);
  for (double scale : {0.001, 0.005, 0.02}) {
    const std::vector<double> w = nbs::detail::region_weights(s.mesh, region, boundary, scale);
    REQUIRE(w.size() == region.size());
    for (std::size_t i = 0; i < region.size(); ++i) {
      double d2 = std::numeric_limits<double>::infinity();
      const Vec3 p = s.mesh.position(region[i]);
      for (nbs::VertexId b : boundary) d2 = std::min(d2, (Vec3(s.mesh.position(b)) - p).squaredNorm());
      REQUIRE(w[i] == nbs::boundary_distance_weight(std::sqrt(d2), scale));
    }
  }
}
