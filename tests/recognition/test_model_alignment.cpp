// SPDX-License-Identifier: BSD-3-Clause
// align_models / merge_models (Sec. 5.3) on analytic data: the samples of an L block without its bottom, and of the
// same block turned onto its side without its new bottom, aligned against the known turn.

#include "nbs_catch.hpp"

#include <numbers>

#include "../sim/test_meshes.hpp"
#include "nbs/recognition/model_alignment.hpp"
#include "nbs/sim/reorientation.hpp"
#include "nbs/sim/surface_samples.hpp"

using namespace nbs;

namespace {

IndexedMesh l_block() {
  IndexedMesh l = test::box_mesh({-0.04, -0.025, 0.0}, {0.04, 0.025, 0.03});
  const IndexedMesh block = test::box_mesh({0.01, -0.025, 0.03}, {0.04, 0.025, 0.06});
  for (const auto& t : block.triangles) l.triangles.push_back({t[0] + 8u, t[1] + 8u, t[2] + 8u});
  l.vertices.insert(l.vertices.end(), block.vertices.begin(), block.vertices.end());
  return l;
}

/// The samples the pedestal does not hide, as oriented points.
OrientedPoints visible_samples(const IndexedMesh& m, std::uint64_t seed) {
  const SurfaceSamples s = sample_surface(m, 20000, seed);
  OrientedPoints p;
  for (std::size_t i = 0; i < s.size(); ++i)
    if (!s.bottom[i]) p.points.push_back(s.points[i]), p.normals.push_back(s.normals[i]);
  return p;
}

}  // namespace

TEST_CASE("align_models finds the turn between two partial models of an L block", "[recognition][alignment]") {
  const IndexedMesh upright = l_block();
  const Placement turn = reorientation_placement(upright);
  const IndexedMesh turned = transformed_mesh(upright, turn.T_turn);
  const ModelAlignment al = align_models(visible_samples(upright, 1), visible_samples(turned, 2));
  const Pose truth = turn.T_turn.inverse();
  double offset = 0.0;
  for (const Vec3& v : turned.vertices) offset = std::max(offset, (al.T_ab * v - truth * v).norm());
  INFO("hypotheses " << al.hypotheses << ", chosen " << al.hypothesis << ", score " << al.score << ", icp "
                     << to_string(al.icp.status) << " " << al.icp.reason << ", offset " << offset);
  CHECK(al.icp.applied());
  CHECK(rotation_angle_between(al.T_ab.linear(), truth.linear()) < std::numbers::pi / 180.0);
  CHECK(offset < 0.001);
  CHECK(al.score > 0.7);
}

TEST_CASE("merge_models: the union in a's frame; bad input is refused", "[recognition][alignment]") {
  IndexedMesh a = test::box_mesh({0, 0, 0}, {0.1, 0.1, 0.1});
  a.normals.assign(a.vertices.size(), Vec3::UnitZ());
  IndexedMesh b = a;
  Pose T = Pose::Identity();
  T.linear() = Mat3(Eigen::AngleAxisd(0.5 * std::numbers::pi, Vec3::UnitX()));
  T.translation() = Vec3(0.2, 0, 0);
  const IndexedMesh m = merge_models(a, b, T);
  REQUIRE(m.vertices.size() == 2 * a.vertices.size());
  REQUIRE(m.normals.size() == m.vertices.size());
  CHECK(m.triangles.back()[0] == b.triangles.back()[0] + a.vertices.size());
  CHECK((m.vertices.back() - T * b.vertices.back()).norm() < 1e-15);
  CHECK((m.normals.back() - Vec3(0, -1, 0)).norm() < 1e-12);
  a.colors.assign(a.vertices.size(), Rgb{200, 10, 10});
  b.colors.assign(b.vertices.size(), Rgb{10, 10, 200});
  const IndexedMesh coloured = merge_models(a, b, T);
  REQUIRE(coloured.colors.size() == coloured.vertices.size());
  CHECK(coloured.colors.front() == a.colors.front());
  CHECK(coloured.colors.back() == b.colors.back());
  CHECK_NOTHROW(coloured.validate());
  b.colors.pop_back();
  CHECK_THROWS_AS(merge_models(a, b, T), InvalidArgument);  // a colour count that is not the vertex count
  b.colors.clear();
  CHECK(merge_models(a, b, T).colors.empty());  // colours only if both have them
  b.normals.clear();
  CHECK(merge_models(a, b, T).normals.empty());  // normals only if both have them

  Pose sheared = T;
  sheared.linear()(0, 1) = 0.3;
  CHECK_THROWS_AS(merge_models(a, b, sheared), InvalidArgument);
  b.triangles.push_back({0, 1, 99});
  CHECK_THROWS_AS(merge_models(a, b, T), InvalidArgument);
  CHECK_THROWS_AS(oriented_points(b), InvalidArgument);  // no normals
  ModelAlignmentSetting bad;
  bad.refined_hypotheses = 0;
  CHECK_THROWS_AS(align_models(visible_samples(a, 1), visible_samples(a, 2), bad), InvalidArgument);
}
