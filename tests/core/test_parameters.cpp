// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include <limits>

#include "nbs/core/parameters.hpp"
#include "nbs/mesh/streaming_mesh_settings.hpp"

TEST_CASE("Parameters default to Tab. 4.3 in SI units", "[core]") {
  const nbs::Parameters p;
  REQUIRE_NOTHROW(p.validate());
  CHECK(p.reduction_radius_m == 0.0005);
  CHECK(p.normal_radius_m == 0.004);
  CHECK(p.mesh_radius_m == 0.006);
  CHECK(p.voxel_size_m == 0.005);
  CHECK(p.boundary_penalty_threshold == 5);
  CHECK(p.min_boundary_edges == 15);
  CHECK(p.quality_weight == 0.7);
  CHECK(p.target_coverage == 0.8);
  CHECK(p.target_density == 0.2);
  CHECK(p.max_scans == 30);
}

TEST_CASE("Parameters::validate names the bad field and value", "[core]") {
  nbs::Parameters p;
  p.voxel_size_m = -1.0;
  REQUIRE_THROWS_WITH(p.validate(), nbs_test::Contains("voxel_size_m") && nbs_test::Contains("-1"));
  p = nbs::Parameters{};
  p.quality_weight = std::numeric_limits<double>::quiet_NaN();
  REQUIRE_THROWS_WITH(p.validate(), nbs_test::Contains("quality_weight"));
  p = nbs::Parameters{};
  p.max_scans = 0;
  REQUIRE_THROWS_WITH(p.validate(), nbs_test::Contains("max_scans"));
}

TEST_CASE("Parameters::validate cross-checks the fields that bound each other, naming both values", "[core]") {
  nbs::Parameters p;
  p.reduction_radius_m = 0.005;  // R_n = 0.004 < R_r < R_m = 0.006
  REQUIRE_THROWS_WITH(p.validate(), nbs_test::Contains("normal_radius_m (0.004") && nbs_test::Contains("0.005"));
  const nbs::StreamingMeshSettings s = [] {
    nbs::StreamingMeshSettings m;
    m.reduction_radius_m = 0.005;
    return m;
  }();
  CHECK_THROWS_WITH(s.validate(), nbs_test::Contains("normal_radius_m (0.004"));  // the same rule, written once
  p = nbs::Parameters{};
  p.reduction_radius_m = 0.006;
  p.normal_radius_m = 0.01;
  REQUIRE_THROWS_WITH(p.validate(), nbs_test::Contains("mesh_radius_m (0.006"));
  p.reduction_radius_m = 0.0059;
  CHECK_NOTHROW(p.validate());
  p = nbs::Parameters{};
  p.voxel_size_m = 0.2;  // larger than the object (0.16 m)
  REQUIRE_THROWS_WITH(p.validate(), nbs_test::Contains("voxel_size_m (0.2") && nbs_test::Contains("object_size_m (0.16"));
  p.voxel_size_m = 0.159;
  CHECK_NOTHROW(p.validate());
}
