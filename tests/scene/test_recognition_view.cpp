// SPDX-License-Identifier: BSD-3-Clause
// Planned recognition views (nbs/explore/recognition_view.hpp): the view that reaches the most unobserved voxels of
// an ambiguous cluster's box, checked against a brute-force count over the same beams.
#include "nbs_catch.hpp"

#include <cmath>
#include <limits>
#include <set>
#include <vector>

#include "nbs/explore/recognition_view.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"
#include "nbs/space/ray_traversal.hpp"

using namespace nbs;
using namespace nbs::explore;

namespace {

using ViewSpace = ProbabilisticVoxelSpace<>;

// A 64 × 48 camera (range 0.1–2 m): small, so that 48 candidates with every ray stay fast.
AreaSensor small_camera() {
  AreaSensor s;
  s.width_px = 64;
  s.height_px = 48;
  s.range = {0.1, 2.0};
  return s;
}

// The object's box [−0.05, 0.05]² × [0, 0.1] in a 1 cm space over the table; one scan from −y along +y ends on the
// plane y = 0 across the box: the box's half y < 0 is observed free, y = 0 occupied, y > 0 unobserved.
const Aabb kObject{Vec3(-0.05, -0.05, 0.0), Vec3(0.05, 0.05, 0.1)};
ViewSpace half_seen_space() {
  ViewSpace space(0.01, Aabb{Vec3(-0.3, -0.3, -0.01), Vec3(0.3, 0.3, 0.3)});
  Scan s;
  for (double x = -0.045; x < 0.05; x += 0.01)
    for (double z = 0.005; z < 0.1; z += 0.01) {
      Pose p = Pose::Identity();
      p.translation() = Vec3(x, -0.29, z);
      s.profile_poses.push_back(p);
      s.add_point(Vec3(x, 0.005, z), static_cast<std::uint32_t>(s.profile_poses.size() - 1));
    }
  for (int k = 0; k < 3; ++k) space.integrate(s);  // three hits: occupied under the thesis model
  return space;
}

// Brute force: distinct unobserved voxels of `box` that the beams reach, each beam stopping after its first occupied voxel.
std::size_t unobserved_reached(const ViewSpace& space, const std::vector<Ray>& rays, const Aabb& box) {
  const KeyBox keys{*space.grid().key_of(box.min), *space.grid().key_of(box.max)};
  const KeyBox inside = space.bounds_keys();
  std::set<std::uint64_t> seen;
  for (const Ray& r : rays)
    traverse_segment(space.grid(), r.origin, r.end, [&](const VoxelKey& k) {
      if (!inside.contains(k)) return true;
      if (keys.contains(k) && !space.observed(k)) seen.insert(k.pack());
      return !space.occupied(k);
    });
  return seen.size();
}

}  // namespace

TEST_CASE("plan_recognition_view looks at the unobserved side of the box (brute-force count)", "[scene][explore][aim]") {
  const ViewSpace space = half_seen_space();
  REQUIRE(space.occupied(*space.grid().key_of(Vec3(0.0, 0.005, 0.05))));
  REQUIRE_FALSE(space.observed(*space.grid().key_of(Vec3(0.0, 0.03, 0.05))));
  const AreaSensor camera = small_camera();
  OverviewRingSetting ring;
  RecognitionViewSetting st;
  st.sampling = {1, 1};
  const std::vector<Aabb> boxes{kObject};
  const RecognitionView v = plan_recognition_view(space, camera, boxes, ring, 0, st);
  CHECK(v.target.isApprox(kObject.center(), 1e-12));
  CHECK((v.eye - v.target).norm() == Approx(ring.distance_m));
  CHECK(v.eye.y() > v.target.y());  // from the unobserved side
  std::vector<Ray> rays;
  append_candidate_rays(LinearScanPath(Viewpoint::look_at(v.eye, v.target)), camera, st.sampling, rays);
  const double best = static_cast<double>(unobserved_reached(space, rays, kObject));
  CHECK(v.score == best);
  CHECK(best > 0.0);
  // No other candidate of the setting reaches more (the oracle over all of them).
  for (const double el : st.elevations_rad)
    for (int k = 0; k < st.azimuths; ++k) {
      const double a = ring.step_azimuth(0) + 2.0 * 3.141592653589793 * k / st.azimuths;
      const Vec3 eye = v.target + ring.distance_m * unit_from_angles(a, el);
      std::vector<Ray> r;
      append_candidate_rays(LinearScanPath(Viewpoint::look_at(eye, v.target)), camera, st.sampling, r);
      CHECK(static_cast<double>(unobserved_reached(space, r, kObject)) <= best);
    }
  // The same choice with 2 threads.
  st.threads = 2;
  const RecognitionView v2 = plan_recognition_view(space, camera, boxes, ring, 0, st);
  CHECK(v2.eye == v.eye);
  CHECK(v2.score == v.score);
}

TEST_CASE("plan_recognition_view: bad input throws", "[scene][explore][aim]") {
  const ViewSpace space = half_seen_space();
  const AreaSensor camera = small_camera();
  const OverviewRingSetting ring;
  CHECK_THROWS_AS(plan_recognition_view(space, camera, std::span<const Aabb>{}, ring, 0), InvalidArgument);
  const std::vector<Aabb> empty_box{Aabb{}};
  CHECK_THROWS_AS(plan_recognition_view(space, camera, empty_box, ring, 0), InvalidArgument);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<Aabb> nan_box{Aabb{Vec3(nan, 0, 0), Vec3(0.1, 0.1, 0.1)}};
  CHECK_THROWS_AS(plan_recognition_view(space, camera, nan_box, ring, 0), InvalidArgument);
  const std::vector<Aabb> boxes{kObject};
  RecognitionViewSetting bad;
  bad.azimuths = 0;
  CHECK_THROWS_AS(plan_recognition_view(space, camera, boxes, ring, 0, bad), InvalidArgument);
  bad = {};
  for (const double el : {2.0, -0.1, 0.0}) {
    bad.elevations_rad = {el};
    CHECK_THROWS_AS(plan_recognition_view(space, camera, boxes, ring, 0, bad), InvalidArgument);
  }
  bad = {};
  bad.elevations_rad.clear();
  CHECK_THROWS_AS(plan_recognition_view(space, camera, boxes, ring, 0, bad), InvalidArgument);
}
