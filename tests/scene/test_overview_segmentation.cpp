// SPDX-License-Identifier: BSD-3-Clause
// End to end: a generated scene, one overview frame of an area sensor (Embree), segmentation; the ground-truth
// labels of the frame are the oracle.
#include "nbs_catch.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <set>

#include "nbs/embree/scene_scanner.hpp"
#include "nbs/io/load_mesh.hpp"
#include "nbs/mesh/normalize.hpp"
#include "nbs/scene/segmentation.hpp"
#include "nbs/sensor/presets.hpp"
#include "test_meshes.hpp"

using namespace nbs;
using namespace nbs::scene;

namespace {
/// The Asus Xtion Pro at half resolution (320 x 240, same field of view and noise): a fast test frame.
AreaSensor half_xtion() {
  AreaSensor s = presets::asus_xtion_pro();
  s.width_px = 320;
  s.height_px = 240;
  return s;
}

std::vector<ObjectSpec> three_objects() {
  return {{"box", test::box_mesh(Vec3(-0.04, -0.03, 0.0), Vec3(0.04, 0.03, 0.10))},
          {"ball", test::uv_sphere(Vec3(0.0, 0.0, 0.045), 0.045, 16, 24)},
          {"well", test::cube_with_well(0.08, 0.04, 0.03)}};
}

struct Outcome {
  std::size_t visible = 0, clusters = 0, matched = 0, fragments = 0;
  double worst_purity = 1.0;
  std::size_t points = 0;  ///< of the frame
  double segment_ms = 0.0;
  double worst_main_share = 1.0;  ///< least share of an object's clustered points in its largest cluster.
};

/// Segments one overview frame and checks it against the labels: one cluster per visible object (≥ min_size
/// labelled points above the plane clearance), each ≥ 95 % one object's points. With `fragments_allowed`, an object
/// may have further (pure) clusters: surface pieces that occlusion cuts off from the rest in a single view.
Outcome run(const std::vector<ObjectSpec>& objects, std::uint64_t seed, const SceneSettings& st, const Vec3& eye,
            bool fragments_allowed = false) {
  const SimulatedScene scene = generate_scene(objects, st, seed);
  const embree::SceneScanner scanner(scene);
  const Viewpoint view = Viewpoint::look_at(eye, Vec3(0.0, 0.0, st.table_height_m + 0.04));
  const embree::OverviewFrame f = scanner.overview(view, half_xtion(), seed);
  REQUIRE(f.labels.size() == f.scan.points.size());
  Outcome out;
  SegmentationSettings seg_st;
  const auto t0 = std::chrono::steady_clock::now();
  const Segmentation seg = segment_scene(f.scan.points, seg_st);
  out.points = f.scan.points.size();
  out.segment_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  REQUIRE(seg.status == SegmentationStatus::ok);
  CHECK(std::abs(seg.plane.plane.z_at(0.0, 0.0) - st.table_height_m) < 0.002);
  CHECK(seg.plane.plane.normal.z() > std::cos(0.01));
  std::map<int, std::size_t> above;  // labelled points above the plane clearance, per object
  for (std::size_t i = 0; i < f.scan.points.size(); ++i)
    if (f.labels[i] >= 0 && seg.plane.plane.signed_distance(f.scan.points[i]) > seg_st.plane_clearance_m)
      ++above[f.labels[i]];
  std::set<int> visible;
  for (const auto& [id, n] : above)
    if (n >= seg_st.cluster.min_size) visible.insert(id);
  out.visible = visible.size();
  out.clusters = seg.objects.size();
  std::set<int> found;
  std::map<int, std::vector<std::size_t>> sizes;  // cluster sizes per majority object
  for (const ObjectHypothesis& h : seg.objects) {
    std::map<int, std::size_t> count;
    for (auto i : h.indices) ++count[f.labels[i]];
    const auto best = std::max_element(count.begin(), count.end(),
                                       [](const auto& a, const auto& b) { return a.second < b.second; });
    const double purity = static_cast<double>(best->second) / static_cast<double>(h.indices.size());
    out.worst_purity = std::min(out.worst_purity, purity);
    CAPTURE(seed, best->first, purity, h.indices.size(), h.centroid.transpose());
    CHECK(best->first >= 0);
    CHECK(purity >= 0.95);
    sizes[best->first].push_back(h.indices.size());
    if (!found.insert(best->first).second) {
      ++out.fragments;
      CHECK(fragments_allowed);  // an object split into two clusters
    }
    if (best->first >= 0) {
      // the box stands on the table and holds the object's visible part
      const auto& obj = scene.objects[static_cast<std::size_t>(best->first)];
      CHECK(std::abs(h.box.min.z() - st.table_height_m) < 0.003);
      CHECK(h.box.max.z() <= obj.mesh.bounds().max.z() + seg_st.box_margin_m + 0.01);
      CHECK(h.box.contains(h.centroid));
    }
  }
  out.matched = found.size();
  for (auto& [id, v] : sizes) {
    std::size_t total = 0;
    for (auto n : v) total += n;
    out.worst_main_share = std::min(out.worst_main_share, static_cast<double>(*std::max_element(v.begin(), v.end())) /
                                                              static_cast<double>(total));
  }
  CHECK(found == visible);
  return out;
}
}  // namespace

TEST_CASE("overview frame + segmentation: one pure cluster per visible object", "[scene][embree]") {
  SceneSettings st;
  st.table_height_m = 0.75;
  st.table_size_x_m = 0.4;
  st.table_size_y_m = 0.3;
  st.min_gap_m = 0.03;
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    const Outcome o = run(three_objects(), seed, st, Vec3(0.7, 0.3, st.table_height_m + 0.6));
    std::printf("scene seed %llu: %zu visible objects, %zu clusters, %zu matched, worst purity %.4f; "
                "segment_scene %.1f ms for %zu points\n",
                static_cast<unsigned long long>(seed), o.visible, o.clusters, o.matched, o.worst_purity, o.segment_ms,
                o.points);
    CHECK(o.visible >= 2);
  }
}

TEST_CASE("overview frame + segmentation of the bunny, the mug and the car", "[scene][embree]") {
  IndexedMesh bunny = load_mesh(std::string(NBS_DATA_DIR) + "/meshes/stanford-bunny.obj");
  normalize_on_pedestal(bunny, 0.16, UpAxis::y);
  const std::string dir = std::string(NBS_DATA_DIR) + "/meshes/test-objects/";
  const std::vector<ObjectSpec> objects{
      {"bunny", std::move(bunny)}, {"mug", load_mesh(dir + "mug.obj")}, {"car", load_mesh(dir + "car.obj")}};
  SceneSettings st;
  st.table_height_m = 0.7;
  st.table_size_x_m = 0.6;
  st.table_size_y_m = 0.45;
  st.min_gap_m = 0.03;
  for (std::uint64_t seed : {1u, 2u}) {
    const Outcome o = run(objects, seed, st, Vec3(-0.5, -0.6, st.table_height_m + 0.7), /*fragments_allowed*/ true);
    std::printf("bunny/mug/car seed %llu: %zu visible objects, %zu clusters (%zu fragments), %zu matched, worst purity "
                "%.4f, least share of an object's points in its largest cluster %.3f; segment_scene %.1f ms for %zu points\n",
                static_cast<unsigned long long>(seed), o.visible, o.clusters, o.fragments, o.matched, o.worst_purity,
                o.worst_main_share, o.segment_ms, o.points);
    CHECK(o.worst_main_share >= 0.8);
    CHECK(o.visible >= 2);
  }
}

TEST_CASE("overview frame: labels and determinism", "[scene][embree]") {
  const auto objects = three_objects();
  const SimulatedScene scene = generate_scene(objects, SceneSettings{}, 5);
  const embree::SceneScanner scanner(scene);
  const Viewpoint view = Viewpoint::look_at(Vec3(0.0, -0.6, 0.7), Vec3::Zero());
  const embree::OverviewFrame a = scanner.overview(view, half_xtion(), 9, 1);
  const embree::OverviewFrame b = scanner.overview(view, half_xtion(), 9, 2);
  CHECK(a.scan.points == b.scan.points);
  CHECK(a.labels == b.labels);
  std::size_t table = 0;
  for (std::size_t i = 0; i < a.labels.size(); ++i) {
    CHECK(a.labels[i] >= -1);
    CHECK(a.labels[i] < 3);
    if (a.labels[i] == -1) {
      ++table;
      CHECK(std::abs(a.scan.points[i].z()) < 0.02);  // table points lie on z = 0 (noise ≈ 1.3 mm at 0.9 m)
    }
  }
  CHECK(table > a.labels.size() / 2);
}
