// SPDX-License-Identifier: BSD-3-Clause
// StreamingMesh input validation (issue 17): a scan, pose or point the mesh cannot take throws InvalidArgument naming
// the index and the value, and changes nothing — the oracle is a twin mesh that never saw the bad input.
#include "nbs_catch.hpp"

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "mesh_test_util.hpp"

using nbs::Vec3;
using nbs::test::down_at;

namespace {
const double kNan = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();

/// Everything observable of a mesh: counters, scan index and pose, vertices, normals, faces.
struct Fingerprint {
  std::vector<std::uint64_t> counters;
  std::vector<double> numbers;
  std::vector<nbs::VertexId> faces;
  bool operator==(const Fingerprint&) const = default;
};

Fingerprint fingerprint(const nbs::StreamingMesh& m) {
  Fingerprint f;
  const nbs::StreamingStats& s = m.stats();
  f.counters = {s.received, s.outside, s.too_close, s.stored, s.meshed, s.normal_failures, m.current_scan(),
                m.vertex_count(), m.face_count()};
  const auto& pose = m.current_sensor().matrix();
  f.numbers.assign(pose.data(), pose.data() + 16);
  for (std::size_t v = 0; v < m.vertex_count(); ++v) {
    const auto id = static_cast<nbs::VertexId>(v);
    for (int k = 0; k < 3; ++k) {
      f.numbers.push_back(m.position(id)[k]);
      f.numbers.push_back(m.normal(id)[k]);
    }
  }
  m.for_each_face([&](const nbs::MeshFace& t) { f.faces.insert(f.faces.end(), {t.a, t.b, t.c}); });
  return f;
}

nbs::Scan plane_scan(double x, unsigned seed) {
  static const nbs::test::PlanePatch plane(0.02, 0.02);
  return nbs::test::scan_path(plane, down_at(x, 0.01, 0.15), 0.02, nbs::test::StripeSensor{}, seed);
}

/// A mesh after one good scan, with either pass-through setting.
void prime(nbs::StreamingMesh& m) { (void)m.integrate(plane_scan(0.0, 1)); }

nbs::Aabb box(double h) {
  nbs::Aabb b;
  b.extend(Vec3::Constant(-h));
  b.extend(Vec3::Constant(h));
  return b;
}
}  // namespace

TEST_CASE("StreamingMesh::integrate rejects a bad scan with its index and value and changes nothing",
          "[mesh][validation]") {
  struct Bad {
    const char* what;
    std::function<void(nbs::Scan&)> spoil;
    std::string message;  // a part the error must contain
  };
  const std::vector<Bad> cases = {
      {"NaN point", [](nbs::Scan& s) { s.points[17] = Vec3(0.0, kNan, 0.0); }, "scan point 17"},
      {"infinite point", [](nbs::Scan& s) { s.points[3] = Vec3(kInf, 0.0, 0.0); }, "scan point 3"},
      {"NaN pose", [](nbs::Scan& s) { s.profile_poses[2](0, 3) = kNan; }, "scan profile pose 2"},
      {"scaled pose", [](nbs::Scan& s) { s.profile_poses[4].linear() *= 1.01; }, "scan profile pose 4"},
      {"mirrored pose",
       [](nbs::Scan& s) { s.profile_poses[1].linear() = s.profile_poses[1].linear() * Vec3(1, 1, -1).asDiagonal(); },
       "determinant"},
      {"count mismatch", [](nbs::Scan& s) { s.profile_of_point.pop_back(); }, "profile indices"},
      {"profile index", [](nbs::Scan& s) { s.profile_of_point[9] = 1u << 30; }, "scan point 9 refers to profile"},
      {"point at 1e30 m",
       [](nbs::Scan& s) { s.points[21] = s.origin(21) + 1e30 * s.line_of_sight(21); }, "scan point 21"},
      {"point at 1e7 m", [](nbs::Scan& s) { s.points[5] = Vec3(1e7, 0.0, 0.0); }, "coordinate range"},
      {"point at its sensor origin", [](nbs::Scan& s) { s.points[8] = s.origin(8); }, "coincides with its sensor"},
  };
  for (const bool boxed : {false, true}) {
    for (const Bad& bad : cases) {
      INFO(bad.what << (boxed ? ", with a pass-through box" : ", no box"));
      nbs::StreamingMesh m(nbs::Parameters{}, boxed ? box(0.5) : nbs::Aabb{}),
          twin(nbs::Parameters{}, boxed ? box(0.5) : nbs::Aabb{});
      prime(m);
      prime(twin);
      nbs::Scan scan = plane_scan(0.004, 2);
      REQUIRE(scan.size() > 100);
      bad.spoil(scan);
      const Fingerprint before = fingerprint(m);
      REQUIRE_THROWS_AS(m.integrate(scan), nbs::InvalidArgument);
      CHECK_THROWS_WITH(m.check_scan(scan), nbs_test::Contains(bad.message));
      CHECK(fingerprint(m) == before);
      // What follows is as if the bad scan had never come.
      const nbs::Scan next = plane_scan(0.008, 3);
      CHECK(m.integrate(next) == twin.integrate(next));
      CHECK(fingerprint(m) == fingerprint(twin));
    }
  }
}

TEST_CASE("StreamingMesh: an empty scan changes nothing; begin_scan and insert validate", "[mesh][validation]") {
  nbs::StreamingMesh m;
  prime(m);
  const Fingerprint before = fingerprint(m);
  nbs::Scan empty;
  CHECK(m.integrate(empty) == 0);
  empty.profile_poses.push_back(down_at(0.0, 0.0, 0.2).pose());
  CHECK(m.integrate(empty) == 0);
  CHECK(fingerprint(m) == before);
  empty.profile_poses[0].linear() *= 2.0;
  CHECK_THROWS_WITH(m.integrate(empty), nbs_test::Contains("scan profile pose 0"));

  nbs::Pose sheared = nbs::Pose::Identity();
  sheared.linear()(0, 1) = 0.1;
  CHECK_THROWS_WITH(m.begin_scan(sheared), nbs_test::Contains("begin_scan") && nbs_test::Contains("not orthonormal"));
  nbs::Pose nan_pose = nbs::Pose::Identity();
  nan_pose.translation().x() = kNan;
  CHECK_THROWS_AS(m.begin_scan(nan_pose), nbs::InvalidArgument);

  const Vec3 down(0, 0, -1), p(0.001, 0.002, 0.0);
  CHECK_THROWS_WITH(m.insert(Vec3(kNan, 0, 0), down), nbs_test::Contains("not finite"));
  CHECK_THROWS_AS(m.insert(Vec3(0, kInf, 0), down), nbs::InvalidArgument);
  CHECK_THROWS_WITH(m.insert(p, Vec3::Zero()), nbs_test::Contains("line of sight"));
  CHECK_THROWS_AS(m.insert(p, Vec3(kNan, 0, 1)), nbs::InvalidArgument);
  CHECK_THROWS_AS(m.insert(p, Vec3(1e-13, 0, 0)), nbs::InvalidArgument);
  CHECK_THROWS_WITH(m.insert(Vec3(0, 0, -1e7), down), nbs_test::Contains("coordinate range"));
  CHECK(fingerprint(m) == before);
}

TEST_CASE("StreamingMesh coordinate range: half the spatial hash's key range, exact at its edge", "[mesh][validation]") {
  // Analytic: 21 bits per axis hold cells -(2^20 - 1) .. 2^20 - 1; points keep to half of that, (2^20 - 2) / 2 cells
  // of R_m / 2 each.
  for (const double rm : {0.006, 0.002, 0.02}) {
    nbs::StreamingMeshSettings s;
    s.mesh_radius_m = rm;
    const double limit = 0.5 * (1048576.0 - 2.0) * (rm / 2.0);
    CHECK(s.max_abs_coordinate_m() == Approx(limit).epsilon(1e-15));
    nbs::StreamingMesh m(s);
    const Vec3 down(0, 0, -1);
    CHECK_NOTHROW(m.insert(Vec3(limit, -limit, 0.0), down));
    CHECK_NOTHROW(m.insert(Vec3(-limit, 0.0, limit), down));
    CHECK_THROWS_AS(m.insert(Vec3(std::nextafter(limit, kInf), 0.0, 0.0), down), nbs::InvalidArgument);
    CHECK_THROWS_AS(m.insert(Vec3(0.0, 0.0, -std::nextafter(limit, kInf)), down), nbs::InvalidArgument);
    CHECK(m.vertex_count() == 2);
    CHECK(m.stats().received == 2);
  }
  CHECK(nbs::StreamingMeshSettings{}.max_abs_coordinate_m() == Approx(1572.861).epsilon(1e-9));
}

TEST_CASE("StreamingMesh far from the origin: a plane near the range's edge meshes like one at the origin",
          "[mesh][validation]") {
  // Far from the origin the hash cells stay distinct (no clamping), so the same scan moved by ~1 km gives the
  // same mesh up to the rounding of its coordinates (< 1.2e-13 m) and the order in which neighbours are visited.
  // Oracle: the mesh of the unmoved scan.
  nbs::StreamingMesh here, far;
  const nbs::Scan scan = plane_scan(0.0, 4);
  nbs::Scan moved = scan;
  const Vec3 shift(1024.0, -512.0, 256.0);
  for (auto& pose : moved.profile_poses) pose.translation() += shift;
  for (auto& p : moved.points) p += shift;
  (void)here.integrate(scan);
  (void)far.integrate(moved);
  REQUIRE(here.face_count() > 100);
  CHECK(far.vertex_count() == here.vertex_count());
  CHECK(std::abs(static_cast<double>(far.face_count()) - static_cast<double>(here.face_count())) <=
        0.01 * static_cast<double>(here.face_count()));
}
