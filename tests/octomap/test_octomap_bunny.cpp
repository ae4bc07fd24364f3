// SPDX-License-Identifier: BSD-3-Clause
// Issue 3's cross-check on real data: the native log-odds space and OctoMap's own insertion classify >= 99.9 % of
// voxels identically after the same LSP scans of the bundled bunny (Embree simulated scanner, DLR LSP with the
// noise of Eq. 4.39, the 13 initial scan paths of Sec. 4.7.2 at 0.3 m).
#include "nbs_catch.hpp"

#include <vector>

#include "nbs/embree/simulated_scanner.hpp"
#include "nbs/io/load_mesh.hpp"
#include "nbs/mesh/normalize.hpp"
#include "nbs/octomap/insert_scan.hpp"
#include "nbs/sensor/presets.hpp"
#include "nbs/sim/initial_scan_paths.hpp"
#include "octomap/classification_agreement.hpp"
#include "space/support/synthetic_scan.hpp"

namespace {

struct BunnyScans {
  nbs::Aabb box;
  std::vector<nbs::Scan> scans;  // points and sensor origins rounded to float, OctoMap's point type
  BunnyScans() {
    nbs::IndexedMesh m = nbs::load_mesh(NBS_DATA_DIR "/meshes/stanford-bunny.obj");
    nbs::normalize_on_pedestal(m, 0.16, nbs::UpAxis::y);
    const nbs::Aabb b = m.bounds();
    box = {nbs::test::to_float(b.min - nbs::Vec3(0.01, 0.01, 0.0)), nbs::test::to_float(b.max + nbs::Vec3::Constant(0.01))};
    const nbs::embree::SimulatedScanner scanner(m);
    const auto sensor = nbs::presets::dlr_lsp();
    std::uint64_t seed = 300;
    for (const auto& path : nbs::initial_scan_paths(box, 0.3)) {
      nbs::Scan s = scanner.scan(path, sensor, seed++);
      for (auto& p : s.points) p = nbs::test::to_float(p);
      for (auto& pose : s.profile_poses) pose.translation() = nbs::test::to_float(pose.translation());
      scans.push_back(std::move(s));
    }
  }
};
const BunnyScans& bunny() {
  static const BunnyScans b;
  return b;
}

}  // namespace

TEST_CASE("bunny: native log-odds space classifies >= 99.9 % of voxels like OctoMap's insertion", "[octomap][oracle][bunny]") {
  const auto& b = bunny();
  const auto [resolution, scans] = GENERATE(std::pair{0.005, 13}, std::pair{0.002, 3});
  nbs::test::NativeLogOddsSpace native(resolution, b.box);
  auto ref = nbs::octomap::bbx_limited_octree(resolution, b.box);
  std::size_t points = 0;
  for (int i = 0; i < scans; ++i) {
    (void)native.integrate(b.scans[i]);
    nbs::octomap::insert_scan(ref, b.scans[i]);
    points += b.scans[i].size();
  }
  const auto r = nbs::test::classification_agreement(native, ref);
  INFO("resolution " << resolution << " m, " << scans << " scans, " << points << " points: voxels " << r.total
                     << ", identical " << r.same << " (" << 100.0 * r.share() << " %), occupied " << r.occupied
                     << ", only in OctoMap " << r.only_ref);
  REQUIRE(points > 100000);
  REQUIRE(r.occupied > 1000);
  REQUIRE(r.share() >= 0.999);
}
