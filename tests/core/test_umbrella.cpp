// SPDX-License-Identifier: BSD-3-Clause
// nbs/nbs.hpp on its own: it must compile stand-alone (this file includes nothing else) and give every folder.
#include "nbs/nbs.hpp"

#include "nbs_catch.hpp"

TEST_CASE("the umbrella header nbs/nbs.hpp gives a symbol of every folder", "[core][umbrella]") {
  const nbs::Pose pose = nbs::Pose::Identity();  // core
  CHECK(nbs::CandidateStatus::empty_mesh != nbs::CandidateStatus::no_holes);  // candidates
  CHECK(nbs::utility_color(1.0) == nbs::Rgb{0, 255, 0});  // io
  CHECK(nbs::IndexedMesh{}.vertices.empty());  // mesh
  CHECK(nbs::GrippedSetup{}.fingers.empty());  // gripped
  CHECK(nbs::format_method(nbs::parse_method("C_H")) == "C_H");  // planner
  CHECK(nbs::HypothesisQuality{}.q_h() == 0.0);  // recognition
  CHECK(nbs::FreeFlyingSensor{}.joint_count() == 6);  // robot
  CHECK(nbs::presets::dlr_lsp().range.max_m > 0.0);  // sensor
  CHECK(nbs::scan_path_length({}) == 0.0);  // sim
  CHECK(nbs::VoxelKey{1, 2, 3}.x == 1);  // space
  CHECK(nbs::MaxScansReached(3).max_scans == 3);  // termination
  CHECK(nbs::voxel_entropy(0.5) > 0.0);  // utility
  CHECK(nbs::PlatformPenalty{}.multiplier(0.0) == 1.0);  // workspace
  CHECK(pose.translation().norm() == 0.0);
}
