#include <catch2/catch.hpp>

#include <limits>

#include "nbs/core/parameters.hpp"

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
  REQUIRE_THROWS_WITH(p.validate(), Catch::Contains("voxel_size_m") && Catch::Contains("-1"));
  p = nbs::Parameters{};
  p.quality_weight = std::numeric_limits<double>::quiet_NaN();
  REQUIRE_THROWS_WITH(p.validate(), Catch::Contains("quality_weight"));
  p = nbs::Parameters{};
  p.max_scans = 0;
  REQUIRE_THROWS_WITH(p.validate(), Catch::Contains("max_scans"));
}
