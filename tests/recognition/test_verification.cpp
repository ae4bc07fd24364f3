// SPDX-License-Identifier: BSD-3-Clause
// Recognition of a database model in a synthetic area-sensor scan at a known pose: PPF matching, verification by
// rendering (q_h, Eq. 3.10), validation against the voxel space (v_h, Eq. 3.11), ICP refinement.
#include "nbs_catch.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>

#include "nbs/explore/scene_exploration.hpp"
#include "nbs/recognition/hypothesis_validation.hpp"
#include "nbs/recognition/hypothesis_verification.hpp"
#include "nbs/recognition/ppf_match.hpp"
#include "nbs/recognition/refine_pose.hpp"
#include "nbs/registration/scan_normals.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"
#include "nbs/sim/surface_samples.hpp"
#include "../sim/test_meshes.hpp"
#include "nbs_temp_dir.hpp"

using namespace nbs;
using namespace nbs::test;

namespace {

void append(IndexedMesh& to, const IndexedMesh& m) {
  const auto base = static_cast<std::uint32_t>(to.vertices.size());
  to.vertices.insert(to.vertices.end(), m.vertices.begin(), m.vertices.end());
  for (auto t : m.triangles) to.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

/// An asymmetric object of three boxes standing on z = 0 (model frame), 0.12 × 0.08 × 0.12 m.
IndexedMesh step_object() {
  IndexedMesh m = box_mesh(Vec3(-0.06, -0.04, 0.0), Vec3(0.06, 0.04, 0.04));
  append(m, box_mesh(Vec3(0.01, -0.04, 0.04), Vec3(0.06, 0.0, 0.12)));
  append(m, box_mesh(Vec3(-0.06, 0.0, 0.04), Vec3(-0.03, 0.04, 0.07)));
  return m;
}

IndexedMesh placed(const IndexedMesh& m, const Pose& t) {
  IndexedMesh out = m;
  for (Vec3& v : out.vertices) v = t * v;
  return out;
}

Aabb box_of(const IndexedMesh& m) {
  Aabb b;
  for (const Vec3& v : m.vertices) b.extend(v);
  return b;
}

struct SyntheticScan {
  AreaSensor sensor;
  Scan scan;     ///< the whole frame (table and object)
  Scan cluster;  ///< the object's points (rays that hit the object's triangles)
  Pose truth;    ///< T_WM
};

/// The step object at a known pose on a 1 m table (z = 0), seen by a 160 × 120 area sensor from 0.45 m at about 38°
/// elevation (the eye turned by `azimuth_rad` about the vertical through the target), ray cast with the brute-force
/// caster; Gaussian range noise σ (seeded).
SyntheticScan synthetic_scan(const IndexedMesh& object, double sigma_m, std::uint64_t seed, double azimuth_rad = 0.0) {
  SyntheticScan s;
  s.truth = Eigen::Translation3d(0.05, -0.03, 0.0) * Eigen::AngleAxisd(0.7, Vec3::UnitZ());
  IndexedMesh world = box_mesh(Vec3(-0.5, -0.5, -0.02), Vec3(0.5, 0.5, 0.0));
  const std::size_t kTableTriangles = world.triangles.size();
  append(world, placed(object, s.truth));
  const BruteForceRayCaster caster(world);
  s.sensor.width_px = 160, s.sensor.height_px = 120, s.sensor.range = {0.2, 2.0};
  const Vec3 target(0.05, -0.03, 0.05);
  const Vec3 eye = target + Eigen::AngleAxisd(azimuth_rad, Vec3::UnitZ()) * Vec3(-0.3525, -0.0525, 0.2775);
  Pose t_ws = Pose::Identity();
  const Vec3 z = (target - eye).normalized(), x = z.cross(Vec3::UnitZ()).normalized();
  t_ws.linear() << x, z.cross(x), z;  // y = z × x points down in the image
  t_ws.translation() = eye;
  s.scan.profile_poses = {t_ws};
  s.cluster.profile_poses = {t_ws};
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  for (const Vec3& d : s.sensor.frame_directions(Viewpoint(t_ws))) {
    ++s.scan.rays_cast;
    const auto hit = caster.first_hit(eye, d, s.sensor.range.max_m);
    if (!hit || !s.sensor.range.contains(hit->distance)) continue;
    const Vec3 p = eye + (hit->distance + sigma_m * g(rng)) * d;
    s.scan.add_point(p, 0);
    if (hit->triangle >= kTableTriangles) s.cluster.add_point(p, 0);
  }
  return s;
}

OrientedPoints cluster_with_normals(const Scan& cluster) {
  const std::vector<Vec3> n = estimate_scan_normals(cluster, {.radius_m = 0.006});
  OrientedPoints out;
  for (std::size_t i = 0; i < cluster.size(); ++i)
    if (n[i].squaredNorm() > 0.0) out.points.push_back(cluster.points[i]), out.normals.push_back(n[i]);
  return out;
}

double angle_of(const Pose& a, const Pose& b) { return rotation_angle_between(a.linear(), b.linear()); }

}  // namespace

TEST_CASE("render_range_image at the true pose reproduces the measured depths of the object (noise-free)",
          "[recognition]") {
  const IndexedMesh object = step_object();
  const SyntheticScan s = synthetic_scan(object, 0.0, 1);
  const RangeImage measured = range_image(s.sensor, s.scan.profile_poses[0], s.cluster.points);
  const BruteForceRayCaster model(object);
  const RangeImage rendered = render_range_image(model, box_of(object), s.truth, measured, 2);
  std::size_t both = 0, only_one = 0;
  double worst = 0.0;
  for (std::size_t i = 0; i < measured.depth.size(); ++i) {
    const bool a = std::isfinite(measured.depth[i]), b = std::isfinite(rendered.depth[i]);
    if (a && b) ++both, worst = std::max(worst, std::abs(measured.depth[i] - rendered.depth[i]));
    only_one += a != b;
  }
  INFO("object pixels " << both << ", pixels in one image only " << only_one);
  CHECK(both == s.cluster.size());  // one cluster point per pixel
  CHECK(both > 1000);
  CHECK(only_one == 0);
  CHECK(worst < 1e-9);
  const HypothesisQuality q = verify_hypothesis(model, box_of(object), s.truth, measured, 0.001);
  CHECK(q.q_h() == 1.0);
  // The pixel rectangle of the box is exact: rendering every pixel gives the same image.
  Aabb everything;
  everything.extend(Vec3::Constant(-100.0)), everything.extend(Vec3::Constant(100.0));
  const RangeImage all = render_range_image(model, everything, s.truth, measured);
  for (std::size_t i = 0; i < all.depth.size(); ++i)
    REQUIRE(std::isfinite(all.depth[i]) == std::isfinite(rendered.depth[i]));
  CHECK_THROWS_WITH(render_range_image(model, Aabb{}, s.truth, measured), Catch::Contains("model_box"));
  RangeImage bad = measured;
  bad.depth.pop_back();
  CHECK_THROWS_WITH(verify_hypothesis(model, box_of(object), s.truth, bad, 0.001), Catch::Contains("19199 depths"));
}

TEST_CASE("recognition in a synthetic scan: matched, verified by q_h, validated by v_h, refined by ICP; a model "
          "not in the scene is rejected",
          "[recognition]") {
  const IndexedMesh object = step_object();
  const SyntheticScan s = synthetic_scan(object, 0.0005, 2);
  const OrientedPoints samples = oriented_points(sample_surface(object, 20000, 3));
  const PpfModel model(samples);
  const OrientedPoints scene = cluster_with_normals(s.cluster);
  const RangeImage cluster = range_image(s.sensor, s.scan.profile_poses[0], s.cluster.points);
  const BruteForceRayCaster caster(object);
  constexpr double kTolerance = 0.005;

  const std::vector<PoseHypothesis> h = match_ppf(model, scene);
  REQUIRE(!h.empty());
  // The thesis verifies every hypothesis and keeps the best q_h.
  std::size_t best = 0;
  std::vector<double> q(h.size());
  for (std::size_t k = 0; k < h.size(); ++k) {
    q[k] = verify_hypothesis(caster, box_of(object), h[k].pose, cluster, kTolerance).q_h();
    if (q[k] > q[best]) best = k;
  }
  const Pose found = h[best].pose;
  const double et = (found.translation() - s.truth.translation()).norm(), er = angle_of(found, s.truth);
  std::printf("step object: %zu cluster points, %zu hypotheses; best q_h %.3f (hypothesis %zu): %.2f mm, %.2f deg\n",
              s.cluster.size(), h.size(), q[best], best, 1e3 * et, er * 180 / std::numbers::pi);
  CHECK(et < 0.01);
  CHECK(er < 0.15);
  CHECK(q[best] > 0.3);

  const RefinedPose refined = refine_pose(samples, found, s.cluster);
  REQUIRE(refined.icp.applied());
  const double rt = (refined.pose.translation() - s.truth.translation()).norm(), rr = angle_of(refined.pose, s.truth);
  const double q_refined = verify_hypothesis(caster, box_of(object), refined.pose, cluster, kTolerance).q_h();
  std::printf("  refined (%d ICP iterations): %.2f mm, %.2f deg, q_h %.3f\n", refined.icp.iterations, 1e3 * rt,
              rr * 180 / std::numbers::pi, q_refined);
  CHECK(rt < 0.002);
  CHECK(rr < 0.02);
  CHECK(q_refined > 0.85);

  // v_h: the voxel space of three frames from views 20° apart (the thesis model takes one beam per voxel and
  // direction and needs three to bring a free voxel below p = 0.25, two for an occupied one above 0.75). The object
  // at its pose: its visible faces occupied, the rest unknown. Lifted 10 cm towards the sensor it floats in
  // observed free space.
  ProbabilisticVoxelSpace<> space(0.005, Aabb{Vec3(-0.2, -0.2, -0.01), Vec3(0.25, 0.2, 0.25)});
  for (int k = -1; k <= 1; ++k) (void)space.integrate(synthetic_scan(object, 0.0005, 11 + k, 0.35 * k).scan);
  const OrientedPoints vertices = oriented_points(sample_surface(object, 4000, 4));
  const HypothesisValidation at_truth = validate_hypothesis(space, std::span<const Vec3>(vertices.points), refined.pose);
  const Pose lifted = Eigen::Translation3d(-0.1 * s.scan.profile_poses[0].linear().col(2)) * refined.pose;
  const HypothesisValidation floating = validate_hypothesis(space, std::span<const Vec3>(vertices.points), lifted);
  std::printf("  v_h at the pose %.3f (free %zu, unknown %zu, occupied %zu); lifted 10 cm %.3f\n", at_truth.v_h(),
              at_truth.free, at_truth.unknown, at_truth.occupied, floating.v_h());
  CHECK(at_truth.valid());
  CHECK(!floating.valid());

  // A sphere of the object's size is not in the scene: its best hypothesis has a low q_h.
  const IndexedMesh sphere = uv_sphere(Vec3(0, 0, 0.06), 0.06, 16, 32);
  const PpfModel sphere_model(oriented_points(sample_surface(sphere, 20000, 3)));
  const BruteForceRayCaster sphere_caster(sphere);
  double sphere_q = 0.0;
  for (const PoseHypothesis& hs : match_ppf(sphere_model, scene))
    sphere_q = std::max(sphere_q, verify_hypothesis(sphere_caster, box_of(sphere), hs.pose, cluster, kTolerance).q_h());
  std::printf("  a sphere of its size: best q_h %.3f\n", sphere_q);
  CHECK(sphere_q < 0.5 * q[best]);
}

TEST_CASE("validate_hypothesis: v_h of Eq. 3.11 on hand-built probabilities", "[recognition]") {
  // p = 0.2 for x < 0 (free), 0.25 ≤ p < 0.75 by x in [0, 1), 0.75 from x = 1 (occupied).
  struct Ramp {
    [[nodiscard]] double probability(const Vec3& x) const {
      return x.x() < 0.0 ? 0.2 : x.x() < 1.0 ? 0.25 + 0.5 * x.x() : 0.75;
    }
  };
  static_assert(OccupancyProbability<Ramp>);
  const std::vector<Vec3> v = {Vec3(-1, 0, 0), Vec3(0, 0, 0), Vec3(0.999, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)};
  const HypothesisValidation r = validate_hypothesis(Ramp{}, std::span<const Vec3>(v), Pose::Identity());
  CHECK(r.free == 1);
  CHECK(r.unknown == 2);
  CHECK(r.occupied == 2);
  CHECK(r.v_h() == Approx((0.5 * 2 + 2) / (1 + 0.5 * 2 + 2)));
  CHECK(r.valid());
  // Moved by −1.5 in x: x = −2.5, −1.5, −0.501, −0.5 free, 0.5 unknown.
  const HypothesisValidation m =
      validate_hypothesis(Ramp{}, std::span<const Vec3>(v), Pose(Eigen::Translation3d(-1.5, 0, 0)));
  CHECK(m.free == 4);
  CHECK(m.unknown == 1);
  CHECK(m.occupied == 0);
  CHECK(m.v_h() == Approx(0.5 / 4.5));
  CHECK(!m.valid());
  // About the threshold 0.66: 2 occupied against 1 free is 0.667 (valid), 1 against 1 is 0.5 (invalid); only
  // unknown vertices give 1 (nothing contradicts the hypothesis).
  CHECK(HypothesisValidation{1, 0, 2}.valid());
  CHECK(!HypothesisValidation{1, 0, 1}.valid());
  CHECK(HypothesisValidation{0, 4, 0}.v_h() == 1.0);
  CHECK(HypothesisValidation{}.v_h() == 0.0);
  const std::vector<Vec3> nan = {Vec3(std::numeric_limits<double>::quiet_NaN(), 0, 0)};
  CHECK_THROWS_WITH(validate_hypothesis(Ramp{}, std::span<const Vec3>(nan), Pose::Identity()),
                    Catch::Contains("vertex 0"));
}

TEST_CASE("PpfRecogniser keeps its own model meshes: learned from a temporary, the database grown, still recognised",
          "[recognition]") {
  nbs_test::TempDir dir("nbs_ppf_recogniser_");
  ModelDatabase db = ModelDatabase::create(dir.path / "db");
  const SyntheticScan s = synthetic_scan(step_object(), 0.0005, 2);
  ProbabilisticVoxelSpace<> space(0.005, Aabb{Vec3(-0.2, -0.2, -0.01), Vec3(0.25, 0.2, 0.25)});
  for (int k = -1; k <= 1; ++k) (void)space.integrate(synthetic_scan(step_object(), 0.0005, 11 + k, 0.35 * k).scan);
  explore::PpfRecogniser<BruteForceRayCaster, ProbabilisticVoxelSpace<>> recogniser(db, s.sensor, space);
  {
    IndexedMesh temporary = step_object();
    recogniser.learn("step", temporary);
    temporary.vertices.assign(temporary.vertices.size(), Vec3(9, 9, 9));  // a borrowed mesh would now be wrong
  }
  recogniser.learn("sphere", uv_sphere(Vec3(0, 0, 0.06), 0.06, 16, 32));  // the database's vector grows
  const explore::Recognition r = recogniser.recognise({}, s.cluster);
  const double et = (r.pose.translation() - s.truth.translation()).norm();
  std::printf("PpfRecogniser: %s, q_h %.3f, v_h %.3f, %.2f mm\n", r.model.c_str(), r.q_h, r.v_h, 1e3 * et);
  CHECK(r.model == "step");
  CHECK(r.q_h > 0.85);
  CHECK(et < 0.002);
  CHECK(r.accepted);
}

namespace {

/// A mug of 16-gon prism (radius 40 mm, 100 mm high, z up from 0) with a box handle on +x (40–65 mm out,
/// z 30–70 mm): its body is symmetric under turns of 22.5°, the handle tells them apart.
IndexedMesh prism_mug() {
  IndexedMesh m;
  const int n = 16;
  const double r = 0.04, h = 0.1;
  for (int k = 0; k < n; ++k) {
    const double a = 2.0 * std::numbers::pi * k / n;
    m.vertices.emplace_back(r * std::cos(a), r * std::sin(a), 0.0);
    m.vertices.emplace_back(r * std::cos(a), r * std::sin(a), h);
  }
  const auto bottom = static_cast<std::uint32_t>(m.vertices.size());
  m.vertices.emplace_back(0.0, 0.0, 0.0);
  m.vertices.emplace_back(0.0, 0.0, h);
  for (std::uint32_t k = 0; k < static_cast<std::uint32_t>(n); ++k) {
    const std::uint32_t a0 = 2 * k, a1 = a0 + 1, b0 = 2 * ((k + 1) % n), b1 = b0 + 1;
    m.triangles.push_back({a0, b0, b1});
    m.triangles.push_back({a0, b1, a1});
    m.triangles.push_back({bottom, b0, a0});
    m.triangles.push_back({bottom + 1, a1, b1});
  }
  append(m, box_mesh(Vec3(0.038, -0.01, 0.03), Vec3(0.065, 0.01, 0.07)));
  return m;
}

}  // namespace

TEST_CASE("PpfRecogniser: a mug with its handle hidden is ambiguous (another turn fits as well), with it in view "
          "it is not",
          "[recognition][ambiguity]") {
  nbs_test::TempDir dir("nbs_ppf_ambiguity_");
  ModelDatabase db = ModelDatabase::create(dir.path / "db");
  // synthetic_scan places the object turned by 0.7 rad: its handle points at 40°; an eye azimuth of 0.55 rad puts
  // the sensor at 220°, straight in front of the handle's far side (hidden behind the body and below its rim).
  const double hidden = 0.55, facing = 0.55 + std::numbers::pi;
  for (const double az : {hidden, facing}) {
    INFO("eye azimuth " << az);
    const SyntheticScan s = synthetic_scan(prism_mug(), 0.0003, 4, az);
    ProbabilisticVoxelSpace<> space(0.005, Aabb{Vec3(-0.2, -0.2, -0.01), Vec3(0.25, 0.2, 0.25)});
    (void)space.integrate(s.scan);
    explore::PpfRecogniserSetting rs;
    REQUIRE(rs.reject_ambiguous);  // the default
    explore::PpfRecogniser<BruteForceRayCaster, ProbabilisticVoxelSpace<>> recogniser(db, s.sensor, space, rs);
    if (db.models().empty()) recogniser.learn("mug", prism_mug());
    const explore::Recognition r = recogniser.recognise({}, s.cluster);
    std::printf("ambiguity, azimuth %.2f: %s q_h %.3f (alternative %.3f) v_h %.3f ambiguous %d, %.1f mm\n", az,
                r.model.c_str(), r.q_h, r.q_h_alternative, r.v_h, int(r.ambiguous),
                1e3 * (r.pose.translation() - s.truth.translation()).norm());
    CHECK(r.model == "mug");
    if (az == hidden) {
      CHECK(r.ambiguous);
      CHECK_FALSE(r.accepted);
      CHECK(r.q_h_alternative >= r.q_h - rs.ambiguity_margin);
    } else {
      CHECK_FALSE(r.ambiguous);
      CHECK(r.accepted);
      CHECK((r.pose.translation() - s.truth.translation()).norm() < 0.002);
      CHECK(angle_of(r.pose, s.truth) < 2.0 * std::numbers::pi / 180.0);
    }
  }
  explore::PpfRecogniserSetting bad;
  bad.ambiguity_distance = 0.0;
  CHECK_THROWS_WITH(bad.validate(), nbs_test::Contains("ambiguity_distance"));
  bad = {};
  bad.ambiguity_margin = -0.1;
  CHECK_THROWS_WITH(bad.validate(), nbs_test::Contains("ambiguity_margin"));
}

namespace {

/// The step object (in the database) and `neighbour` (not in it) 2 mm beside it, scanned as one (noise seed
/// `seed`), with a voxel space of three more views of them (seeds space_seed − 1 … + 1) for v_h.
struct TouchingScan {
  SyntheticScan s;
  ProbabilisticVoxelSpace<> space{0.005, Aabb{Vec3(-0.2, -0.2, -0.01), Vec3(0.3, 0.25, 0.25)}};
  TouchingScan(const IndexedMesh& neighbour, std::uint64_t seed, std::uint64_t space_seed) {
    IndexedMesh both = step_object();
    append(both, neighbour);
    s = synthetic_scan(both, 0.0003, seed);
    for (int k = -1; k <= 1; ++k)
      (void)space.integrate(synthetic_scan(both, 0.0003, space_seed - 1 + static_cast<std::uint64_t>(k + 1), 0.35 * k).scan);
  }
  /// The cluster's points in the step object's true box grown by margin_m.
  [[nodiscard]] std::size_t in_step_box(double margin_m) const {
    const Aabb b = box_of(step_object());
    const Aabb grown{b.min - Vec3::Constant(margin_m), b.max + Vec3::Constant(margin_m)};
    std::size_t n = 0;
    for (const Vec3& p : s.cluster.points) n += grown.contains(s.truth.inverse() * p);
    return n;
  }
};

}  // namespace

TEST_CASE("PpfRecogniser::recognise_part: a known object touching an unknown box is found in part of the cluster",
          "[recognition][parts]") {
  nbs_test::TempDir dir("nbs_ppf_part_");
  ModelDatabase db = ModelDatabase::create(dir.path / "db");
  // A larger box 2 mm beside the step object: one cluster of both.
  const TouchingScan t(box_mesh(Vec3(0.062, -0.09, 0.0), Vec3(0.2, 0.09, 0.12)), 3, 21);
  const SyntheticScan& s = t.s;
  const ProbabilisticVoxelSpace<>& space = t.space;
  explore::PpfRecogniser<BruteForceRayCaster, ProbabilisticVoxelSpace<>> recogniser(db, s.sensor, space);
  recogniser.learn("step", step_object());
  const explore::Recognition whole = recogniser.recognise({}, s.cluster);
  const explore::PartRecognition part = recogniser.recognise_part({}, s.cluster);
  const std::size_t on_step = t.in_step_box(0.001);  // the cluster's points on the step object
  const double et = (part.recognition.pose.translation() - s.truth.translation()).norm();
  std::printf("recognise_part: whole q_h %.3f accepted %d; part %s q_h %.3f v_h %.3f, %zu of %zu points (%zu on the "
              "object), %.2f mm, %.2f deg\n",
              whole.q_h, int(whole.accepted), part.recognition.model.c_str(), part.recognition.q_h,
              part.recognition.v_h, part.points.size(), s.cluster.size(), on_step, 1e3 * et,
              angle_of(part.recognition.pose, s.truth) * 180.0 / std::numbers::pi);
  REQUIRE_FALSE((whole.accepted || whole.ambiguous));  // the box's points cost the whole its q_h ((N_m / N_c)²)
  CHECK(part.recognition.accepted);
  CHECK(part.recognition.model == "step");
  CHECK(et < 0.002);
  CHECK(angle_of(part.recognition.pose, s.truth) < 2.0 * std::numbers::pi / 180.0);
  CHECK(std::is_sorted(part.points.begin(), part.points.end()));
  CHECK(part.points.size() >= on_step);
  CHECK(part.points.size() < s.cluster.size());
  const auto part_with = [&](const explore::PpfRecogniserSetting& setting) {
    explore::PpfRecogniser<BruteForceRayCaster, ProbabilisticVoxelSpace<>> r(db, s.sensor, space, setting);
    return r.recognise_part({}, s.cluster);
  };
  // Without part models the whole cluster is returned, not recognised.
  explore::PpfRecogniserSetting none;
  none.part_models = 0;
  const explore::PartRecognition p0 = part_with(none);
  CHECK(p0.points.size() == s.cluster.size());
  CHECK_FALSE(p0.recognition.accepted);
  // A crop must rate q_h >= part_min_q_h (this one rates about 0.6).
  explore::PpfRecogniserSetting strict;
  strict.part_min_q_h = 0.9;
  const explore::PartRecognition p9 = part_with(strict);
  CHECK(p9.points.size() == s.cluster.size());
  CHECK_FALSE(p9.recognition.accepted);
  none.part_min_points = 2;
  CHECK_THROWS_WITH(none.validate(), nbs_test::Contains("part_min_points must be >= 3, got 2"));
  none = {};
  none.part_min_q_h = 1.5;
  CHECK_THROWS_WITH(none.validate(), nbs_test::Contains("part_min_q_h must be in [0, 1], got 1.5"));
}

TEST_CASE("PpfRecogniser::recognise_part: a small neighbour of a recognised object is left outside the part",
          "[recognition][parts]") {
  nbs_test::TempDir dir("nbs_ppf_part_small_");
  ModelDatabase db = ModelDatabase::create(dir.path / "db");
  // A 4 cm cube 2 mm beside the step object: the whole cluster is still accepted as the step object.
  const TouchingScan t(box_mesh(Vec3(0.062, -0.02, 0.0), Vec3(0.102, 0.02, 0.04)), 4, 31);
  const SyntheticScan& s = t.s;
  explore::PpfRecogniser<BruteForceRayCaster, ProbabilisticVoxelSpace<>> recogniser(db, s.sensor, t.space);
  recogniser.learn("step", step_object());
  REQUIRE(recogniser.recognise({}, s.cluster).accepted);  // as a whole
  const explore::PartRecognition part = recogniser.recognise_part({}, s.cluster);
  // The oracle: the cluster's points more than 1 cm outside the step object's true box (the cube's, bar its side
  // within the 1 cm margin).
  const std::size_t outside = s.cluster.size() - t.in_step_box(0.01);
  std::printf("recognise_part, small neighbour: %s q_h %.3f accepted %d, %zu of %zu points, %zu outside the true "
              "box\n", part.recognition.model.c_str(), part.recognition.q_h, int(part.recognition.accepted),
              part.points.size(), s.cluster.size(), outside);
  REQUIRE(outside >= 50);
  CHECK(part.recognition.accepted);
  CHECK(part.recognition.model == "step");
  CHECK(part.points.size() + outside == s.cluster.size());
  // The part is recognised on its own: without the cube's points against it (Eq. 3.10's (N_m / N_c)²) it rates
  // higher than the whole.
  const explore::Recognition whole = recogniser.recognise({}, s.cluster);
  CHECK(part.recognition.q_h > whole.q_h);
  // A crop that rates below part_min_q_h on its own: the whole is not accepted either (a wrong model fitting a
  // piece of the cluster).
  REQUIRE(part.recognition.q_h < 1.0);
  explore::PpfRecogniserSetting strict;
  strict.part_min_q_h = 1.0;
  explore::PpfRecogniser<BruteForceRayCaster, ProbabilisticVoxelSpace<>> picky(db, s.sensor, t.space, strict);
  REQUIRE(picky.recognise({}, s.cluster).accepted);
  const explore::PartRecognition refused = picky.recognise_part({}, s.cluster);
  CHECK_FALSE(refused.recognition.accepted);
  CHECK(refused.recognition.model == "step");
  CHECK(refused.points.size() == s.cluster.size());
}
