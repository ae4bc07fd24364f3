// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <unordered_map>
#include <unordered_set>

#include "mesh_test_util.hpp"
#include "nbs/io/read_ply.hpp"
#include "nbs/mesh/mesh.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"

using nbs::Vec3;
using nbs::test::down_at;

TEST_CASE("open plane patch yields four boundaries of the right types (Alg. 1, Tab. 4.1)", "[mesh]") {
  nbs::test::PlanePatch plane(0.03, 0.03);
  nbs::test::StripeSensor sensor;
  const auto start = down_at(0, 0.04, 0.15);  // s_x = +x_W, s_y = −y_W, s_z = −z_W
  nbs::StreamingMesh mesh;
  mesh.integrate(nbs::test::scan_path(plane, start, 0.08, sensor, 1));
  const auto bs = nbs::detect_boundaries(mesh, mesh.current_sensor(), nbs::Parameters{});
  std::map<nbs::BoundaryType, int> count;
  for (const auto& b : bs) {
    ++count[b.type];
    Vec3 c = Vec3::Zero();
    for (auto v : b.vertices) c += mesh.position(v);
    c /= static_cast<double>(b.vertices.size());
    // Where the border lies relative to the mesh, in sensor axes (boundaries.hpp): left = +s_x, top = +s_y.
    switch (b.type) {
      case nbs::BoundaryType::left: CHECK(c.x() > 0.025); break;
      case nbs::BoundaryType::right: CHECK(c.x() < -0.025); break;
      case nbs::BoundaryType::top: CHECK(c.y() < -0.025); break;
      case nbs::BoundaryType::bottom: CHECK(c.y() > 0.025); break;
    }
    CHECK(static_cast<int>(b.edges.size()) >= nbs::Parameters{}.min_boundary_edges);
    CHECK(b.mean_normal.dot(mesh.current_sensor().linear().col(2)) < 0.0);
  }
  CHECK(bs.size() == 4);
  CHECK(count[nbs::BoundaryType::left] == 1);
  CHECK(count[nbs::BoundaryType::right] == 1);
  CHECK(count[nbs::BoundaryType::top] == 1);
  CHECK(count[nbs::BoundaryType::bottom] == 1);

  SECTION("a sensor looking from behind sees no boundary") {
    nbs::Pose behind = mesh.current_sensor();
    behind.linear() = behind.linear() * Eigen::AngleAxisd(M_PI, Vec3::UnitY()).toRotationMatrix();
    CHECK(nbs::detect_boundaries(mesh, behind, nbs::Parameters{}).empty());
  }
  SECTION("after a new (empty) scan M_cur is empty, so no boundary is searched") {
    mesh.begin_scan(mesh.current_sensor());
    CHECK(nbs::detect_boundaries(mesh, mesh.current_sensor(), nbs::Parameters{}).empty());
  }
}

TEST_CASE("holes punched in a sphere are found with areas within 15 % (Sec. 4.4, Eq. 4.37)", "[mesh]") {
  const double r = 0.04;
  nbs::test::Sphere sphere(Vec3(0, 0, 0), r);
  const std::vector<std::pair<Vec3, double>> punched{{Vec3(0.3, 0.2, 1).normalized(), 0.25},
                                                     {Vec3(-0.4, -0.1, 1).normalized(), 0.2}};
  sphere.holes = punched;
  nbs::test::StripeSensor sensor;
  sensor.fov_rad = 0.6;
  sensor.rays = 400;
  nbs::StreamingMesh mesh;
  mesh.integrate(nbs::test::scan_path(sphere, down_at(0, 0.05, 0.2), 0.1, sensor, 11));
  const auto holes = nbs::find_holes(mesh, nbs::Parameters{});
  for (const auto& [dir, ang] : punched) {
    const Vec3 centre = r * dir;
    const nbs::Hole* best = nullptr;
    for (const auto& h : holes)
      if (!best || (h.center - centre).norm() < (best->center - centre).norm()) best = &h;
    REQUIRE(best != nullptr);
    const double cap = 2.0 * M_PI * r * r * (1.0 - std::cos(ang));  // true missing area
    INFO("hole area " << best->area_m2 << " cap " << cap);
    CHECK((best->center - centre).norm() < 0.25 * r * ang);
    CHECK(best->area_m2 == Approx(cap).epsilon(0.15));
    CHECK(best->normal.dot(dir) > 0.95);
    CHECK(best->largest_direction.norm() == Approx(r * std::sin(ang)).epsilon(0.2));
    // The loop hugs the true rim: every loop vertex within R_m / 2 of the rim circle (geodesic on the sphere).
    double rim_dev = 0.0;
    for (auto v : best->vertices) {
      const double a = std::acos(std::clamp(mesh.position(v).normalized().dot(dir), -1.0, 1.0));
      rim_dev = std::max(rim_dev, std::abs(a - ang) * r);
    }
    INFO("largest rim deviation " << rim_dev << " m");
    CHECK(rim_dev <= 0.5 * nbs::Parameters{}.mesh_radius_m);
  }
}

constexpr double kDomeRadius = 0.04;

/// Streams a hemisphere of radius kDomeRadius on z = 0, scanned once from above (12 profiles), into `mesh`: a cap
/// with one large rim loop.
static void scan_dome(nbs::StreamingMesh& mesh) {
  nbs::test::Sphere dome(Vec3(0, 0, 0), kDomeRadius);
  dome.min_z = 0.0;
  nbs::test::StripeSensor sensor;
  sensor.fov_rad = 0.6;
  sensor.rays = 400;
  mesh.integrate(nbs::test::scan_path(dome, down_at(0, 0.05, 0.2), 0.1, sensor, 12));
}

TEST_CASE("estimated coverage of a scanned dome matches the Eq. 4.35-4.37 oracle", "[mesh]") {
  // Seen from above, the mesh is a spherical cap down to height z0; its rim loop is the only large hole. Eq. 4.37
  // estimates the missing part by the flat rim disk, so ĉ_m = cap / (cap + disk); for a full hemisphere 2/3.
  const double r = kDomeRadius;
  nbs::StreamingMesh mesh;
  scan_dome(mesh);
  const auto holes = nbs::find_all_loops(mesh, nbs::Parameters{});  // the rim loop counts as the hole
  const nbs::Hole* rim = nullptr;
  for (const auto& h : holes)
    if (!rim || h.area_m2 > rim->area_m2) rim = &h;
  REQUIRE(rim != nullptr);
  double z0 = 0.0;
  for (auto v : rim->vertices) z0 += mesh.position(v).z();
  z0 /= static_cast<double>(rim->vertices.size());
  const double cap = 2.0 * M_PI * r * (r - z0), disk = M_PI * (r * r - z0 * z0);
  const double c = nbs::estimated_coverage(mesh, holes);
  INFO("rim height " << z0 << " c_m " << c);
  CHECK(c == Approx(cap / (cap + disk)).epsilon(0.05));
  CHECK(nbs::filled_area(mesh) == Approx(cap).epsilon(0.05));
}

TEST_CASE("estimated coverage from unseen loops: Eq. 4.35 with each loop weighted by its unseen fan share", "[mesh]") {
  // The scanned dome of the test above: its rim loop is the only large loop, its Eq. 4.37 fan the flat rim disk.
  nbs::StreamingMesh mesh;
  scan_dome(mesh);
  const auto loops = nbs::find_all_loops(mesh, nbs::Parameters{});
  const nbs::Hole* rim = nullptr;
  for (const auto& h : loops)
    if (!rim || h.area_m2 > rim->area_m2) rim = &h;
  REQUIRE(rim != nullptr);
  // find_all_loops ignores h_max: with h_max below the rim's length it still finds every loop, find_holes does not.
  nbs::Parameters short_holes;
  short_holes.hole_max_edges = 50;
  REQUIRE(rim->vertices.size() > 50);
  CHECK(nbs::find_all_loops(mesh, short_holes).size() == loops.size());
  CHECK(nbs::find_holes(mesh, short_holes).size() < loops.size());
  const double filled = nbs::filled_area(mesh);
  double all = 0.0;
  for (const auto& h : loops) all += h.area_m2;
  // Nothing seen: every loop counts in full (Eq. 4.35 over all loops); everything seen: no empty area.
  CHECK(nbs::estimated_coverage_unseen(mesh, loops, [](const Vec3&) { return false; }) ==
        Approx(filled / (filled + all)).epsilon(1e-12));
  CHECK(nbs::estimated_coverage_unseen(mesh, loops, [](const Vec3&) { return true; }) == 1.0);
  // Half of the rim disk seen (x > c_x): the rim's fan is symmetric about its centre, so half of it counts.
  const double cx = rim->center.x();
  const auto half = [&](const Vec3& x) { return x.x() > cx; };
  CHECK(nbs::fan_seen_share(mesh, *rim, half) == Approx(0.5).margin(0.03));
  const double small = all - rim->area_m2;  // the other loops lie anywhere: bound their share by 0 and 1
  const double c = nbs::estimated_coverage_unseen(mesh, loops, half);
  CHECK(c >= filled / (filled + 0.53 * rim->area_m2 + small) - 1e-12);
  CHECK(c <= filled / (filled + 0.47 * rim->area_m2) + 1e-12);
  CHECK(nbs::estimated_coverage_unseen(nbs::StreamingMesh{}, {}, half) == 0.0);
}

TEST_CASE("surface features per voxel (Eqs. 4.26-4.28)", "[mesh]") {
  nbs::test::PlanePatch plane(0.0185, 0.0185);  // border inside the voxel ring [15, 20) mm, not on a voxel face
  nbs::StreamingMesh mesh;
  mesh.integrate(nbs::test::scan_path(plane, down_at(0, 0.03, 0.15), 0.06, nbs::test::StripeSensor{}, 13));
  const nbs::VoxelGrid grid(0.005);
  const auto table = nbs::compute_surface_features(mesh, grid);
  REQUIRE(!table.empty());
  // The plane z = 0 lies on a voxel face, so its vertices fall on both sides of it by noise: the ring is counted per
  // (x, y) column of voxels.
  std::map<std::pair<std::int32_t, std::int32_t>, bool> ring_columns;
  for (const auto& [k, f] : table) {
    REQUIRE_NOTHROW(f.validate());
    CHECK(f.mean_normal.z() > 0.98f);
    const Vec3 c = grid.center(k);
    const bool interior = std::abs(c.x()) < 0.0125 && std::abs(c.y()) < 0.0125;
    const double m = std::max(std::abs(c.x()), std::abs(c.y()));
    const bool at_edge = m > 0.016 && m < 0.019;  // the voxel ring that contains the patch border (|x| or |y| = 18.5 mm)
    if (interior) CHECK(f.border_share < 0.05f);
    if (at_edge) ring_columns[{k.x, k.y}] |= f.border_share > 0.0f;
    if (interior) CHECK(f.mean_density > 0.05f);
  }
  const auto ring = static_cast<double>(ring_columns.size());
  const auto ring_with_border = std::count_if(ring_columns.begin(), ring_columns.end(), [](auto& c) { return c.second; });
  CHECK(ring >= 28);  // 32 voxel columns in the ring
  CHECK(ring_with_border >= 0.9 * ring);
  // Oracle for b_i (Eq. 4.28): the edges of for_each_edge counted per voxel of their midpoint.
  std::unordered_map<nbs::VoxelKey, std::pair<int, int>, nbs::VoxelKeyHash> edge_count;
  mesh.for_each_edge([&](const nbs::MeshEdge& e) {
    if (const auto k = grid.key_of(0.5 * (mesh.position(e.a) + mesh.position(e.b)))) {
      ++edge_count[*k].first;
      edge_count[*k].second += e.is_border() ? 1 : 0;
    }
  });
  for (const auto& [k, f] : table) {
    const auto it = edge_count.find(k);
    const float share = it == edge_count.end() ? 0.0f
                                               : static_cast<float>(static_cast<double>(it->second.second) /
                                                                    static_cast<double>(it->second.first));
    CHECK(f.border_share == share);
  }
  SECTION("incremental update writes only occupied voxels touched by the scan") {
    // A voxel space whose voxels with x ≥ 0 are occupied (p = 0.99), the rest unknown.
    struct HalfSpace : nbs::ProbabilisticVoxelSpace<> {
      using ProbabilisticVoxelSpace::ProbabilisticVoxelSpace;
      using ProbabilisticVoxelSpace::probability;
      double probability(const nbs::VoxelKey& k) const { return k.x >= 0 ? 0.99 : 0.5; }
    } space(0.005, nbs::Aabb{});
    struct {
      nbs::SurfaceFeatureMap map;
    } out;
    // Two overlapping scans of a larger patch: M_cur (the second scan's faces) is part of the mesh.
    const nbs::test::PlanePatch wide(0.03, 0.03);
    nbs::StreamingMesh two;
    two.integrate(nbs::test::scan_path(wide, down_at(0, 0.03, 0.15), 0.03, nbs::test::StripeSensor{}, 15));
    two.integrate(nbs::test::scan_path(wide, down_at(0, 0.01, 0.15), 0.03, nbs::test::StripeSensor{}, 16));
    std::size_t current = 0;
    two.for_each_current_face([&](const nbs::MeshFace&) { ++current; });
    CHECK(current > 0);
    CHECK(current < two.face_count());
    const auto table2 = nbs::compute_surface_features(two, grid);
    const std::size_t written = nbs::update_surface_features(out.map, space, two, nbs::Parameters{});
    CHECK(written == out.map.size());
    CHECK(written > 0);
    std::size_t seen = 0;
    out.map.for_each([&](const nbs::VoxelKey& k, const nbs::SurfaceFeatures& f) {
      CHECK(k.x >= 0);
      CHECK(f.border_share == table2.at(k).border_share);
      ++seen;
    });
    // Oracle for the voxels touched by the scan: those of the vertices of M_cur's edges (in_current_scan).
    std::unordered_set<nbs::VoxelKey, nbs::VoxelKeyHash> touched;
    two.for_each_edge([&](const nbs::MeshEdge& e) {
      if (!two.in_current_scan(e)) return;
      for (nbs::VertexId v : {e.a, e.b})
        if (const auto k = space.grid().key_of(two.position(v)); k && k->x >= 0 && table2.count(*k)) touched.insert(*k);
    });
    CHECK(seen == touched.size());
    for (const auto& k : touched) CHECK(out.map.find(k) != nullptr);
  }
}

namespace {
/// A StreamingMesh seen through the EdgeMesh + DensityMesh members only (no KnowsFaceBorders, no M_cur).
struct PlainView {
  const nbs::StreamingMesh* m;
  std::size_t vertex_count() const { return m->vertex_count(); }
  const Vec3& position(nbs::VertexId v) const { return m->position(v); }
  const Vec3& normal(nbs::VertexId v) const { return m->normal(v); }
  std::size_t face_count() const { return m->face_count(); }
  nbs::VertexId left_vertex(nbs::VertexId a, nbs::VertexId b) const { return m->left_vertex(a, b); }
  template <class F> void for_each_edge(F&& f) const { m->for_each_edge(f); }
  template <class F> void for_each_face(F&& f) const { m->for_each_face(f); }
  double relative_density(nbs::VertexId v) const { return m->relative_density(v); }
};
static_assert(nbs::DensityMesh<PlainView> && !nbs::KnowsFaceBorders<PlainView>);
}  // namespace

TEST_CASE("surface features from the border bits equal those from left_vertex lookups", "[mesh]") {
  const nbs::test::PlanePatch plane(0.03, 0.03);
  nbs::StreamingMesh mesh;
  mesh.integrate(nbs::test::scan_path(plane, down_at(0, 0.03, 0.15), 0.03, nbs::test::StripeSensor{}, 21));
  mesh.integrate(nbs::test::scan_path(plane, down_at(0, 0.0, 0.15), 0.03, nbs::test::StripeSensor{}, 22));
  const nbs::VoxelGrid grid(0.004);
  const auto fast = nbs::compute_surface_features(mesh, grid);
  const auto plain = nbs::compute_surface_features(PlainView{&mesh}, grid);
  REQUIRE(fast.size() == plain.size());
  std::size_t with_border = 0;
  for (const auto& [k, f] : plain) {
    const auto it = fast.find(k);
    REQUIRE(it != fast.end());
    CHECK(it->second.border_share == f.border_share);
    CHECK(it->second.mean_density == f.mean_density);
    CHECK(it->second.mean_normal == f.mean_normal);
    with_border += f.border_share > 0.0f ? 1 : 0;
  }
  CHECK(with_border > 0);
}

TEST_CASE("PLY export round-trips through the reader; IndexedMesh conversion keeps faces", "[mesh]") {
  nbs::test::PlanePatch plane(0.01, 0.01);
  nbs::StreamingMesh mesh;
  mesh.integrate(nbs::test::scan_path(plane, down_at(0, 0.015, 0.15), 0.03, nbs::test::StripeSensor{}, 14));
  const auto im = nbs::to_indexed_mesh(mesh);
  REQUIRE(im.triangles.size() == mesh.face_count());
  REQUIRE(im.normals.size() == im.vertices.size());
  REQUIRE_NOTHROW(im.validate());
  for (bool ascii : {false, true}) {
    const std::string path = std::string("test_mesh_export") + (ascii ? "_a" : "_b") + ".ply";
    nbs::write_mesh_ply(path, mesh, ascii);
    const auto back = nbs::read_ply(path);
    REQUIRE(back.vertices.size() == im.vertices.size());
    REQUIRE(back.triangles.size() == im.triangles.size());
    for (std::size_t i = 0; i < im.vertices.size(); i += 17) CHECK((back.vertices[i] - im.vertices[i]).norm() < 1e-12);
    CHECK(back.triangles[0] == im.triangles[0]);
    std::remove(path.c_str());
  }
}

namespace {
struct Broken {  // two faces sharing the directed edge 0→1, plus a duplicate vertex
  std::vector<Vec3> p{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0, 0, 0)};
  std::size_t vertex_count() const { return p.size(); }
  Vec3 position(nbs::VertexId v) const { return p[v]; }
  Vec3 normal(nbs::VertexId) const { return Vec3::UnitZ(); }
  std::size_t face_count() const { return 2; }
  nbs::VertexId left_vertex(nbs::VertexId, nbs::VertexId) const { return nbs::kNoVertex; }
  template <class F> void for_each_face(F&& f) const { f(nbs::MeshFace{0, 1, 2}); f(nbs::MeshFace{0, 1, 3}); }
  template <class F> void for_each_edge(F&&) const {}
};
}  // namespace

TEST_CASE("invariant checker detects broken meshes", "[mesh]") {
  static_assert(nbs::EdgeMesh<Broken>);
  const auto rep = nbs::check_invariants(Broken{}, 0.1);
  CHECK(!rep.ok());
  CHECK_THAT(rep.problems, nbs_test::Contains("two faces"));
  CHECK_THAT(rep.problems, nbs_test::Contains("apart"));
  CHECK_THAT(rep.problems, nbs_test::Contains("never reported"));
}
