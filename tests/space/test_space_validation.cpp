// SPDX-License-Identifier: BSD-3-Clause
// The unknown area must fit the voxel key range at the chosen voxel size: it is rejected, never clipped silently
// (a 1 nm voxel over a 12 cm box used to shrink the working area to ±1.05 mm without a word).
#include "nbs_catch.hpp"

#include <string>

#include "nbs/space/probabilistic_voxel_space.hpp"
#include "nbs/space/unknown_area_grid.hpp"

namespace {
using nbs::Vec3;
const nbs::Aabb kBox12cm{Vec3(-0.06, -0.06, 0.0), Vec3(0.06, 0.06, 0.12)};
}  // namespace

TEST_CASE("a box that does not fit the key range is rejected with the box and the voxel size", "[space][validation]") {
  // 2^20 voxels of 1 nm = 1.05 mm per side of the origin.
  try {
    nbs::ProbabilisticVoxelSpace<> s(1e-9, kBox12cm);
    FAIL("accepted a 12 cm box at 1 nm voxels; bounds " << s.bounds().min.transpose() << " .. "
                                                         << s.bounds().max.transpose());
  } catch (const nbs::InvalidArgument& e) {
    const std::string msg = e.what();
    CHECK(msg.find("does not fit the key range") != std::string::npos);
    CHECK(msg.find("1e-09") != std::string::npos);  // the voxel size
    CHECK(msg.find("0.12") != std::string::npos);   // the box
  }
  // The edge: at 1 µm the range is ±1.048576 m; a box inside it is kept exactly, one beyond it is rejected.
  const nbs::UnknownAreaGrid inside(1e-6, nbs::Aabb{Vec3(-1.0, -1.0, 0.0), Vec3(1.0, 1.0, 1.0)});
  CHECK(inside.bounds().min == Vec3(-1.0, -1.0, 0.0));
  CHECK(inside.bounds().max == Vec3(1.0, 1.0, 1.0));
  CHECK_THROWS_AS(nbs::UnknownAreaGrid(1e-6, nbs::Aabb{Vec3(-1.0, -1.0, 0.0), Vec3(1.0, 1.0, 1.1)}),
                  nbs::InvalidArgument);
  // The usual case is unchanged: 12 cm at 2 mm.
  const nbs::ProbabilisticVoxelSpace<> ok(0.002, kBox12cm);
  CHECK(ok.bounds().max == kBox12cm.max);
}
