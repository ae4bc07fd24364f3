// SPDX-License-Identifier: BSD-3-Clause
// The bottom by reorientation (Sec. 5.3): an L-shaped block (a box with a block on one end: no rotational symmetry,
// so the alignment has one right answer) is modeled upright, turned onto its largest stable side, modeled again;
// the two models are aligned (PPF + ICP) and merged. Lean: a 128 × 96 depth camera, 5 mm voxels, 4 scans each.

#include "nbs_catch.hpp"
#include "nbs_small_camera.hpp"

#include <cmath>

#include "../sim/test_meshes.hpp"
#include "nbs/embree/simulated_scanner.hpp"
#include "nbs/mesh/conversion.hpp"
#include "nbs/planner/nbs_planner.hpp"
#include "nbs/planner/simulation_loop.hpp"
#include "nbs/recognition/model_alignment.hpp"
#include "nbs/sim/ground_truth.hpp"
#include "nbs/sim/reorientation.hpp"

namespace {

using nbs::Vec3;
using AreaPlanner = nbs::NbsPlanner<nbs::IgQualityUtility, nbs::BoundaryHoleSpace, nbs::AreaSensor>;

using nbs_test::small_camera;

nbs::IndexedMesh l_block() {
  nbs::IndexedMesh l = nbs::test::box_mesh({-0.04, -0.025, 0.0}, {0.04, 0.025, 0.03});
  const nbs::IndexedMesh block = nbs::test::box_mesh({0.01, -0.025, 0.03}, {0.04, 0.025, 0.06});
  for (const auto& t : block.triangles) l.triangles.push_back({t[0] + 8u, t[1] + 8u, t[2] + 8u});
  l.vertices.insert(l.vertices.end(), block.vertices.begin(), block.vertices.end());
  return l;
}

/// One simulated session on `object` (standing on the pedestal z = 0): the planner's final model.
nbs::IndexedMesh model_session(const nbs::IndexedMesh& object, std::uint64_t seed) {
  const nbs::embree::SimulatedScanner scanner(object);
  nbs::Aabb box = object.bounds();
  box.min -= Vec3::Constant(0.02);
  box.max += Vec3::Constant(0.02);
  box.min.z() = 0.0;
  nbs::Parameters params;
  params.voxel_size_m = 0.005;
  AreaPlanner planner(params, small_camera(), box);
  nbs::SimulationSetting sim;
  sim.seed = seed;
  sim.max_scans = 4;
  (void)nbs::run_simulation(planner, scanner, sim);
  return nbs::to_indexed_mesh(planner.mesh());
}

}  // namespace

TEST_CASE("the merged model of a reoriented L block covers its bottom", "[embree][reorientation]") {
  const nbs::IndexedMesh upright = l_block();
  const nbs::Placement turn = nbs::reorientation_placement(upright);
  REQUIRE(turn.face == nbs::SupportFace::minus_y);
  const nbs::IndexedMesh turned = nbs::transformed_mesh(upright, turn.T_turn);

  const nbs::IndexedMesh a = model_session(upright, 3);
  const nbs::IndexedMesh b = model_session(turned, 5);
  const nbs::ModelAlignment al = nbs::align_models(nbs::oriented_points(a), nbs::oriented_points(b));
  const nbs::Pose truth = turn.T_turn.inverse();  // session 2's world → session 1's world
  const double angle = nbs::rotation_angle_between(al.T_ab.linear(), truth.linear());
  double offset = 0.0;  // largest displacement of the object's corners
  for (const Vec3& v : turned.vertices) offset = std::max(offset, (al.T_ab * v - truth * v).norm());
  INFO("hypotheses " << al.hypotheses << ", chosen " << al.hypothesis << ", score " << al.score << ", icp "
                     << nbs::to_string(al.icp.status) << " " << al.icp.reason << ", angle " << angle << " rad, offset "
                     << offset << " m");
  CHECK(angle < 1.0 * 3.14159265 / 180.0);
  CHECK(offset < 0.002);
  CHECK(al.score > 0.5);

  const nbs::IndexedMesh merged = nbs::merge_models(a, b, al.T_ab);
  CHECK(merged.vertices.size() == a.vertices.size() + b.vertices.size());
  CHECK(merged.triangles.size() == a.triangles.size() + b.triangles.size());
  const nbs::GroundTruth gt(upright, {.sample_density_per_m2 = 1.0e6});
  const nbs::Completeness before = gt.completeness(a.vertices);
  const nbs::Completeness after = gt.completeness(merged.vertices);
  const std::size_t bottom = after.samples - after.non_bottom;
  REQUIRE(bottom > 1000);
  const auto bottom_covered = [](const nbs::Completeness& c) { return c.covered - c.covered_non_bottom; };
  INFO("c_b " << before.c_b() << " -> " << after.c_b() << ", bottom covered " << bottom_covered(before) << " -> "
              << bottom_covered(after) << " of " << bottom);
  // The pedestal hides the bottom in session 1: only samples within r = 3 mm of the side faces' lower edges count.
  CHECK(double(bottom_covered(before)) < 0.15 * double(bottom));
  CHECK(double(bottom_covered(after)) > 0.8 * double(bottom));
  CHECK(after.c_b() > before.c_b() + 0.1);
  CHECK(gt.rms_error(merged.vertices) < 0.001);
}
