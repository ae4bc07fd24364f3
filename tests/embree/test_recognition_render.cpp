// SPDX-License-Identifier: BSD-3-Clause
// Recognition in a simulated table-top scene with the Embree render path: the bunny among other objects, scanned by
// the Xtion preset; PPF matching, verification by rendering into the frame (q_h, Eq. 3.10) with an Embree Scene,
// ICP refinement, and a model that is not in the scene rejected.
#include "nbs_catch.hpp"

#include <chrono>
#include <cstdio>
#include <numbers>

#include "nbs/embree/scene.hpp"
#include "nbs/embree/scene_scanner.hpp"
#include "nbs/recognition/hypothesis_verification.hpp"
#include "nbs/recognition/ppf_match.hpp"
#include "nbs/recognition/refine_pose.hpp"
#include "nbs/registration/scan_normals.hpp"
#include "nbs/sensor/presets.hpp"
#include "../recognition/recognition_scenes.hpp"

using namespace nbs;

TEST_CASE("Embree render path: the bunny in a scene is recognised, verified and refined; a sphere is rejected",
          "[embree][recognition]") {
  const std::vector<scene::ObjectSpec> specs = {{"bunny", test::bunny()},
                                                {"box", test::box_mesh(Vec3(-0.04, -0.03, 0), Vec3(0.04, 0.03, 0.1))}};
  const scene::SimulatedScene sc = scene::generate_scene(specs, {}, 3);
  const embree::SceneScanner scanner(sc);
  const Viewpoint view = Viewpoint::look_at(Vec3(-0.45, -0.35, 0.45), sc.objects[0].T_world_object.translation());
  const AreaSensor sensor = presets::asus_xtion_pro();
  const Scan frame = scanner.scan(view, sensor, 5);
  // The bunny's points (ground-truth labels of the points above the table).
  Scan above;
  above.profile_poses = frame.profile_poses;
  for (const Vec3& p : frame.points)
    if (p.z() > 0.002) above.add_point(p, 0);
  const std::vector<int> labels = scanner.labels(above.points, 2);
  Scan cluster;
  cluster.profile_poses = frame.profile_poses;
  for (std::size_t i = 0; i < above.size(); ++i)
    if (labels[i] == 0) cluster.add_point(above.points[i], 0);
  REQUIRE(cluster.size() > 3000);

  // The database model: the placed mesh moved back into the object frame.
  const Pose truth = sc.objects[0].T_world_object;
  IndexedMesh model_mesh = sc.objects[0].mesh;
  for (Vec3& v : model_mesh.vertices) v = truth.inverse() * v;
  Aabb box;
  for (const Vec3& v : model_mesh.vertices) box.extend(v);
  const OrientedPoints samples = oriented_points(sample_surface(model_mesh, 20000, 1));
  const PpfModel model(samples);
  const embree::Scene caster(model_mesh);

  const std::vector<Vec3> n = estimate_scan_normals(cluster, {.radius_m = 0.005});
  OrientedPoints scene_points;
  for (std::size_t i = 0; i < cluster.size(); ++i)
    if (n[i].squaredNorm() > 0.0) scene_points.points.push_back(cluster.points[i]), scene_points.normals.push_back(n[i]);
  const RangeImage image = range_image(sensor, frame.profile_poses[0], cluster.points);
  constexpr double kTolerance = 0.005;

  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<PoseHypothesis> h = match_ppf(model, scene_points);
  const auto t1 = std::chrono::steady_clock::now();
  REQUIRE(!h.empty());
  std::size_t best = 0;
  std::vector<double> q(h.size());
  for (std::size_t k = 0; k < h.size(); ++k) {
    q[k] = verify_hypothesis(caster, box, h[k].pose, image, kTolerance, 2).q_h();
    if (q[k] > q[best]) best = k;
  }
  const auto t2 = std::chrono::steady_clock::now();
  const RefinedPose refined = refine_pose(samples, h[best].pose, cluster);
  const auto t3 = std::chrono::steady_clock::now();
  REQUIRE(refined.icp.applied());
  const double q_refined = verify_hypothesis(caster, box, refined.pose, image, kTolerance, 2).q_h();
  const auto err = [&](const Pose& p) {
    return std::pair((p.translation() - truth.translation()).norm(),
                     rotation_angle_between(p.linear(), truth.linear()) * 180 / std::numbers::pi);
  };
  const auto [et, er] = err(h[best].pose);
  const auto [rt, rr] = err(refined.pose);
  const auto ms = [](auto a, auto b) { return std::chrono::duration<double, std::milli>(b - a).count(); };
  std::printf("bunny in a scene: %zu cluster points; best of %zu hypotheses q_h %.3f, %.2f mm %.2f deg; refined "
              "(%d iterations) q_h %.3f, %.2f mm %.2f deg; match %.0f ms, verify %.1f ms per hypothesis, ICP %.0f ms\n",
              cluster.size(), h.size(), q[best], 1e3 * et, er, refined.icp.iterations, q_refined, 1e3 * rt, rr,
              ms(t0, t1), ms(t1, t2) / static_cast<double>(h.size()), ms(t2, t3));
  CHECK(et < 0.01);
  CHECK(er < 8.0);
  CHECK(q[best] > 0.3);
  CHECK(rt < 0.002);
  CHECK(rr < 1.5);
  CHECK(q_refined > 0.8);

  // A sphere of the bunny's size is not in the scene.
  const IndexedMesh sphere = test::sphere_like_bunny(model_mesh);
  Aabb sphere_box;
  for (const Vec3& v : sphere.vertices) sphere_box.extend(v);
  const embree::Scene sphere_caster(sphere);
  double sphere_q = 0.0;
  for (const PoseHypothesis& hs : match_ppf(PpfModel(oriented_points(sample_surface(sphere, 20000, 1))), scene_points))
    sphere_q = std::max(sphere_q, verify_hypothesis(sphere_caster, sphere_box, hs.pose, image, kTolerance, 2).q_h());
  std::printf("  a sphere of its size: best q_h %.3f\n", sphere_q);
  CHECK(sphere_q < 0.5 * q[best]);
}
