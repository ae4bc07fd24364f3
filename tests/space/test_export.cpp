// SPDX-License-Identifier: BSD-3-Clause
// PLY export and surface-feature storage.
#include "nbs_catch.hpp"

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "nbs/space/export_ply.hpp"
#include "nbs/space/surface_features.hpp"
#include "support/single_beam.hpp"
#include "support/test_boxes.hpp"

namespace {
using nbs::Vec3;
using nbs::VoxelKey;
using nbs_test::kCubeBox;

struct PlyVoxel {
  float x, y, z;
  unsigned char r, g, b;
  float p;
};
std::vector<PlyVoxel> read_ply(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  std::size_t n = 0;
  while (std::getline(in, line) && line != "end_header")
    if (line.rfind("element vertex ", 0) == 0) n = std::stoul(line.substr(15));
  std::vector<PlyVoxel> v(n);
  for (auto& e : v) {
    char buf[19];
    in.read(buf, 19);
    std::memcpy(&e.x, buf, 12);
    std::memcpy(&e.r, buf + 12, 3);
    std::memcpy(&e.p, buf + 15, 4);
  }
  REQUIRE(in.good());
  in.peek();
  REQUIRE(in.eof());
  return v;
}
}  // namespace

TEST_CASE("PLY export: black = free, grey = unknown, white = occupied", "[space][export]") {
  nbs::ProbabilisticVoxelSpace<> space(0.005, kCubeBox);
  (void)space.integrate(nbs::test::beams_scan({{Vec3(-0.3, 0.0025, 0.0025), Vec3(0.0525, 0.0025, 0.0025)}}));
  const auto path = std::filesystem::temp_directory_path() / "nbs_test_space_export.ply";
  const auto n = nbs::write_voxels_ply(space, path);
  REQUIRE(n == nbs::observed_count(space.backend()));
  const auto v = read_ply(path);
  REQUIRE(v.size() == n);
  int dark = 0, bright = 0;
  for (const auto& e : v) {
    const auto k = *space.grid().key_of(Vec3(e.x, e.y, e.z));
    REQUIRE(e.p == Approx(space.probability(k)).margin(1e-6));
    REQUIRE(e.r == std::lround(255.0 * space.probability(k)));
    REQUIRE((e.r == e.g && e.g == e.b));
    dark += e.r < 110 ? 1 : 0;  // free after one pass: p = 0.4
    bright += e.r > 160 ? 1 : 0;
  }
  REQUIRE(dark >= 25);
  REQUIRE(bright >= 1);

  nbs::ProbabilisticVoxelSpace<> small(0.05, kCubeBox);
  const auto m = nbs::write_voxels_ply(small, path, {.include_unknown = true});
  REQUIRE(m == small.bounds_keys().volume());
  for (const auto& e : read_ply(path)) REQUIRE(e.r == 128);  // unknown: p = 0.5
  REQUIRE_THROWS_AS(nbs::write_voxels_ply(small, path, {.include_unknown = true, .max_voxels = 10}),
                    nbs::InvalidArgument);
  std::filesystem::remove(path);
  REQUIRE_THROWS_AS(nbs::write_voxels_ply(space, "/nonexistent-dir/x.ply"), nbs::FileError);
}

TEST_CASE("surface features are stored per voxel and validated", "[space][features]") {
  nbs::SurfaceFeatureMap features;
  nbs::SurfaceFeatures f;
  f.mean_density = 0.25f;
  f.mean_normal = Eigen::Vector3f(0, 0.6f, 0.8f);
  f.border_share = 0.5f;
  features.set(VoxelKey{1, 2, 3}, f);
  REQUIRE(features.size() == 1);
  const auto* g = features.find(VoxelKey{1, 2, 3});
  REQUIRE(g != nullptr);
  REQUIRE(g->mean_density == 0.25f);
  REQUIRE(g->mean_normal == f.mean_normal);
  REQUIRE(g->border_share == 0.5f);
  REQUIRE(features.find(VoxelKey{1, 2, 4}) == nullptr);
  nbs::SurfaceFeatures bad = f;
  bad.mean_density = 1.5f;
  REQUIRE_THROWS_AS(features.set(VoxelKey{0, 0, 0}, bad), nbs::InvalidArgument);
  bad = f;
  bad.mean_normal = Eigen::Vector3f(2, 0, 0);
  REQUIRE_THROWS_AS(features.set(VoxelKey{0, 0, 0}, bad), nbs::InvalidArgument);
  REQUIRE(features.size() == 1);
  REQUIRE(features.erase(VoxelKey{1, 2, 3}));
  REQUIRE(features.size() == 0);
}
