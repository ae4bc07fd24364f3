// SPDX-License-Identifier: BSD-3-Clause
// bench_recognition_scenes: recognition from random single views of seeded table-top scenes with every object in
// the database, as thesis Sec. 5.6.2 (issue 21 items 6 and 7; docs/evaluation.md "Recognition (Sec. 5.6.2)").
//
// Objects (all in the database, all in every scene): the bundled bunny (normalised to 0.16 m, up = y) and the five
// issue-18 test objects car, mug, mushroom, plate, table (data/meshes/test-objects: metres, z up; table.obj is a
// 16 × 10 cm toy table, an object here, not the support). Scenes: generate_scene on a 0.7 × 0.5 m table at z = 0,
// footprints ≥ 20 mm apart, seeds S0 … S0 + scenes − 1 (S0 = NBS_BENCH_RECOGNITION_SEED, default 1).
// Views: per scene `views` Asus Xtion frames (Embree, seeded noise), each from a random seeded pose: azimuth uniform,
// elevation uniform in [35°, 65°], eye 0.7 … 1.0 m from a target uniform in ±0.1 m × ±0.08 m at z = 0.04 m.
// Full: 4 scenes × 12 views = 48 views; quick (NBS_BENCH_QUICK=1): 2 scenes × 6 views = 12 views.
// Close set (NBS_BENCH_RECOGNITION_SCENES=close): footprints 3 … 15 mm apart (SceneSettings::max_gap_m), so neighbours
// nearly touch and partly occlude each other; headlines then end in `_close` (not run by scripts/bench.sh).
// Per view, from scratch (no state carried over, as the thesis): a fresh voxel space (5 mm) holding only this
// frame (v_h's space), segment_scene (defaults), PpfRecogniser (defaults) on every cluster.
//
// Definitions:
//  - visible instance: an object with ≥ 200 frame points whose ground-truth label (SceneScanner::labels) is that
//    object and that lie > 5 mm above the table (the segmentation's plane clearance);
//  - position error: distance between the model's centre (its bounding-box centre, model frame) placed by the
//    hypothesis and by the true pose (not the model-frame origin: a symmetric object flipped onto itself, e.g. the
//    plate turned 180° about its normal, moves its origin 120 mm but not its centre); rotation error: the angle of
//    R_trueᵀ R_est, symmetries not factored out (as the thesis, Fig. 5.20);
//  - recognised: some accepted hypothesis of that view names the object's model with position error < 30 mm;
//  - false positive: an accepted hypothesis whose model's position error is ≥ 30 mm (wrong model or wrong place);
//  - recognition.single_view_recall = recognised / visible instances;
//  - recognition.false_positive_rate = false positives / accepted hypotheses (all views);
//  - pose fusion: per (scene, object) the accepted hypotheses naming its model in views 1..k (PoseFusion,
//    cut-offs 15 mm / 15°, weight q_h); the fused pose's error against k (median and 90th percentile over the
//    (scene, object) pairs that have a fused pose at k), over all objects and over the bunny and the mug alone
//    (the objects without a rotational symmetry, whose rotation error is meaningful).
//  - symmetry-aware (printed, not a headline), the protocol of Hinterstoisser et al. 2012: an accepted hypothesis is
//    right when its surface error against its model's true pose is < 0.1 × the model's bounding-box diagonal —
//    ADD-S for the objects with a symmetry (mushroom: rotational; plate, table: two-fold), ADD for the others
//    (recognition/pose_surface_error.hpp; 2000 surface samples of the model); a visible object is recognised when
//    some accepted hypothesis of its model in that view is right.
// Also printed: per object visible / recognised and why each miss was missed, error distributions of the correct
// hypotheses (median, 90th percentile, max), time per cluster.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <numbers>
#include <optional>
#include <random>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <unistd.h>

#include "headline.hpp"
#include "nbs/core/detail/random.hpp"
#include "nbs/embree/scene.hpp"
#include "nbs/embree/scene_scanner.hpp"
#include "nbs/explore/scene_exploration.hpp"
#include "nbs/io/load_mesh.hpp"
#include "nbs/mesh/normalize.hpp"
#include "nbs/recognition/pose_fusion.hpp"
#include "nbs/recognition/pose_surface_error.hpp"
#include "nbs/scene/scene_generator.hpp"
#include "nbs/scene/segmentation.hpp"
#include "nbs/sensor/presets.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"

namespace {

using namespace nbs;
using Space = ProbabilisticVoxelSpace<>;

constexpr std::size_t kMinVisiblePoints = 200;
constexpr double kPlaneClearanceM = 0.005;
constexpr double kCorrectM = 0.030;
const std::set<std::string> kSymmetric = {"mushroom", "plate", "table"};  // ADD-S; the others ADD

std::vector<scene::ObjectSpec> objects() {
  std::vector<scene::ObjectSpec> out;
  IndexedMesh bunny = load_mesh(NBS_DATA_DIR "/meshes/stanford-bunny.obj");
  normalize_on_pedestal(bunny, 0.16, UpAxis::y);
  out.push_back({"bunny", std::move(bunny)});
  for (const char* n : {"car", "mug", "mushroom", "plate", "table"})
    out.push_back({n, load_mesh(std::string(NBS_DATA_DIR "/meshes/test-objects/") + n + ".obj")});
  return out;
}

double angle_deg(const Pose& a, const Pose& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() * 180.0 / std::numbers::pi;
}

/// q-quantile (nearest rank) of v; NaN if empty.
double quantile(std::vector<double> v, double q) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const auto i = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size())));
  return v[std::min(v.size() - 1, i == 0 ? 0 : i - 1)];
}

void print_distribution(const char* name, const std::vector<double>& v, const char* unit) {
  std::printf("  %-22s n %4zu  median %7.2f  p90 %7.2f  max %7.2f %s\n", name, v.size(), quantile(v, 0.5),
              quantile(v, 0.9), v.empty() ? std::nan("") : *std::max_element(v.begin(), v.end()), unit);
}

/// Why a visible instance was missed.
enum Miss : int { kNoCluster, kOtherModel, kFar, kRejected, kNoHypothesis, kMissKinds };
constexpr std::array<const char*, kMissKinds> kMissNames = {"no own cluster", "other model best", "right model ≥ 30 mm",
                                                            "within 30 mm, rejected", "no hypothesis"};

struct Accepted {
  int view = 0;  ///< view index within the scene
  PoseHypothesis h;
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  const bool quick = bench::quick_mode();
  const int scenes = quick ? 2 : 4, views = quick ? 6 : 12;
  const char* seed_env = std::getenv("NBS_BENCH_RECOGNITION_SEED");
  const std::uint64_t seed0 = seed_env != nullptr ? std::strtoull(seed_env, nullptr, 10) : 1;
  const unsigned threads = 2;
  const char* set_env = std::getenv("NBS_BENCH_RECOGNITION_SCENES");
  const bool close_set = set_env != nullptr && std::string(set_env) == "close";

  const std::vector<scene::ObjectSpec> specs = objects();
  const std::filesystem::path db_dir =
      std::filesystem::temp_directory_path() / ("nbs_bench_recognition_scenes_" + std::to_string(::getpid()));
  std::filesystem::remove_all(db_dir);
  explore::PpfRecogniserSetting rs;
  rs.threads = threads;
  // NBS_BENCH_RECOGNITION_AMBIGUITY=<margin>|off: the q_h margin of PpfRecogniserSetting::reject_ambiguous, or the
  // thesis's recogniser (accept the best placement even when another fits as well); default: the library's.
  if (const char* amb = std::getenv("NBS_BENCH_RECOGNITION_AMBIGUITY"); amb != nullptr && std::string_view(amb) == "off")
    rs.reject_ambiguous = false;
  else
    rs.ambiguity_margin = bench::env_number("NBS_BENCH_RECOGNITION_AMBIGUITY", rs.ambiguity_margin, 0.0, 1.0);
  // NBS_BENCH_RECOGNITION_PARTS=<n>: objects found in one segmentation cluster at most (recognise_clusters'
  // max_parts; 0: one per cluster, the thesis); default: the exploration loop's.
  const int max_parts = static_cast<int>(
      bench::env_number("NBS_BENCH_RECOGNITION_PARTS", explore::ExplorationSetting{}.max_parts, 0, 100, true));
  // NBS_BENCH_RECOGNITION_PART_QH=<q>: PpfRecogniserSetting::part_min_q_h (development runs).
  rs.part_min_q_h = bench::env_number("NBS_BENCH_RECOGNITION_PART_QH", rs.part_min_q_h, 0.0, 1.0);
  std::printf("splits per cluster: at most %d (recognise_clusters), a crop needs q_h >= %.2f\n", max_parts,
              rs.part_min_q_h);
  if (rs.reject_ambiguous)
    std::printf("ambiguous hypotheses refused (q_h margin %.3f, ADD-S max >= %.2f x diagonal)\n", rs.ambiguity_margin,
                rs.ambiguity_distance);
  else
    std::printf("ambiguous hypotheses accepted (NBS_BENCH_RECOGNITION_AMBIGUITY=off)\n");
  ModelDatabase db = ModelDatabase::create(db_dir);
  const double build_s = bench::seconds([&] {
    for (const scene::ObjectSpec& o : specs)
      db.add({o.name, 0.0, {}, {"bundled mesh"}}, o.mesh,
             PpfModel(oriented_points(sample_surface(o.mesh, rs.surface_samples, rs.seed)), rs.model));
  });
  std::printf("database: %zu models, PPF tables built in %.1f s; scenes %d (seeds %llu..%llu) x %d views%s\n",
              db.models().size(), build_s, scenes, static_cast<unsigned long long>(seed0),
              static_cast<unsigned long long>(seed0 + scenes - 1), views, quick ? " (quick)" : "");

  scene::SceneSettings st;
  st.table_size_x_m = 0.7;
  st.table_size_y_m = 0.5;
  st.min_gap_m = close_set ? 0.003 : 0.02;
  if (close_set) st.max_gap_m = 0.015;
  std::printf("scene set: %s (footprints %.0f mm apart%s)\n", close_set ? "close" : "standard", 1e3 * st.min_gap_m,
              close_set ? " or more, each within 15 mm of a neighbour" : " or more");
  const Aabb bounds(Vec3(-0.5 * st.table_size_x_m, -0.5 * st.table_size_y_m, st.table_height_m - 0.01),
                    Vec3(0.5 * st.table_size_x_m, 0.5 * st.table_size_y_m, st.table_height_m + 0.3));
  const AreaSensor xtion = presets::asus_xtion_pro();
  scene::SegmentationSettings seg_setting;
  seg_setting.plane_clearance_m = kPlaneClearanceM;
  // One space for every view, reset per view: the recogniser borrows it.
  Space space(0.005, bounds);
  explore::PpfRecogniser<embree::Scene, Space> recogniser(db, xtion, space, rs);

  std::map<std::string, std::array<int, 2>> per_object;  // visible, recognised
  std::map<std::string, std::array<int, kMissKinds>> misses;
  int visible = 0, recognised = 0, accepted_total = 0, false_positives = 0, clusters_total = 0, parts_total = 0;
  std::vector<double> err_mm, err_deg, fp_per_view;
  double recognise_s = 0.0;
  // Fusion: per scene and object, the accepted hypotheses of its model.
  const std::vector<int> fusion_k = quick ? std::vector<int>{1, 2, 4, 6} : std::vector<int>{1, 2, 4, 6, 8, 10, 12};
  std::map<int, std::array<std::vector<double>, 4>> fused;  // k → (mm, deg) all objects, (mm, deg) bunny and mug
  std::map<std::string, Vec3> centre;  // model frame
  for (const scene::ObjectSpec& o : specs) centre[o.name] = o.mesh.bounds().center();
  const auto position_error = [&](const std::string& model, const Pose& est, const Pose& truth) {
    return (est * centre.at(model) - truth * centre.at(model)).norm();
  };
  std::map<std::string, std::vector<double>> rot_of;  // per object, rotation errors of the recognised
  std::map<std::string, SurfacePoseMetric> surface_metric;  // ADD-S per model
  std::map<std::string, double> diagonal;  // of the model's bounding box
  for (const scene::ObjectSpec& o : specs) {
    surface_metric.emplace(o.name, SurfacePoseMetric(sample_surface(o.mesh, 2000, 5).points));
    diagonal[o.name] = o.mesh.bounds().extent().norm();
  }
  int recognised_adds = 0, false_positives_adds = 0;
  int ambiguous_right = 0, ambiguous_wrong = 0;  // refused as ambiguous, within 30 mm of the truth or not
  std::map<std::string, std::vector<double>> adds_of;  // per model, ADD-S of every accepted hypothesis, mm
  PoseClusterSetting fusion_setting{0.015, 15.0 * std::numbers::pi / 180.0};

  for (int s = 0; s < scenes; ++s) {
    const std::uint64_t scene_seed = seed0 + static_cast<std::uint64_t>(s);
    const scene::SimulatedScene sc = scene::generate_scene(specs, st, scene_seed);
    const embree::SceneScanner scanner(sc);
    std::map<std::string, int> truth_index;
    for (std::size_t k = 0; k < sc.objects.size(); ++k) truth_index[sc.objects[k].name] = static_cast<int>(k);
    std::vector<std::vector<Accepted>> accepted_of(sc.objects.size());
    std::mt19937_64 rng(scene_seed * 7919 + 17);
    const auto u = [&](double lo, double hi) { return lo + (hi - lo) * detail::uniform01(rng); };
    for (int v = 0; v < views; ++v) {
      // y before x: one draw per statement, in the order gcc 12 drew the former one-expression form (the views
      // of the reported figures).
      const double ty = u(-0.08, 0.08), tx = u(-0.1, 0.1);
      const Vec3 target(tx, ty, st.table_height_m + 0.04);
      const double az = u(0.0, 2.0 * std::numbers::pi), el = u(35.0, 65.0) * std::numbers::pi / 180.0,
                   dist = u(0.7, 1.0);
      const Vec3 eye = target + dist * nbs::unit_from_angles(az, el);
      const embree::OverviewFrame f =
          scanner.overview(Viewpoint::look_at(eye, target), xtion, scene_seed * 1000 + static_cast<std::uint64_t>(v),
                           threads);
      space = Space(0.005, bounds);
      (void)space.integrate(f.scan);
      std::vector<std::size_t> object_points(sc.objects.size(), 0);
      for (std::size_t i = 0; i < f.scan.size(); ++i)
        if (f.labels[i] >= 0 && f.scan.points[i].z() > st.table_height_m + kPlaneClearanceM)
          ++object_points[static_cast<std::size_t>(f.labels[i])];
      const scene::Segmentation seg = scene::segment_scene(f.scan.points, seg_setting);
      struct ClusterOutcome {
        int truth = -1;  ///< majority label
        std::size_t truth_points = 0;
        explore::Recognition r;
      };
      std::vector<ClusterOutcome> outcomes;
      std::vector<explore::RecognisedCluster> recognised_clusters;
      if (seg.status == scene::SegmentationStatus::ok)  // else no clusters: every visible object is a miss
        recognise_s += bench::seconds([&] {
          recognised_clusters = explore::recognise_clusters(recogniser, f.scan, seg, seg_setting, max_parts);
        });
      for (const explore::RecognisedCluster& rc : recognised_clusters) {
        ClusterOutcome c;
        std::map<int, std::size_t> votes;
        for (std::size_t i : rc.hypothesis.indices) ++votes[f.labels[i]];
        for (auto [l, n] : votes)
          if (l >= 0 && n > c.truth_points) c.truth = l, c.truth_points = n;
        c.r = rc.record.recognition;
        parts_total += rc.record.split;
        outcomes.push_back(c);
      }
      clusters_total += static_cast<int>(outcomes.size());
      // Accepted hypotheses: correct or false positive.
      std::vector<bool> found(sc.objects.size(), false), found_adds(sc.objects.size(), false);
      int fp_view = 0;
      for (const ClusterOutcome& c : outcomes) {
        if (c.r.ambiguous) {  // refused as ambiguous: would it have been right?
          const int k = truth_index.at(c.r.model);
          const double et =
              position_error(c.r.model, c.r.pose, sc.objects[static_cast<std::size_t>(k)].T_world_object);
          ++(et < kCorrectM && c.truth == k ? ambiguous_right : ambiguous_wrong);
        }
        if (!c.r.accepted) continue;
        ++accepted_total;
        const int k = truth_index.at(c.r.model);
        const Pose& truth = sc.objects[static_cast<std::size_t>(k)].T_world_object;
        const double et = position_error(c.r.model, c.r.pose, truth);
        const SurfacePoseError se = surface_metric.at(c.r.model).error(c.r.pose, truth);
        const double adds = kSymmetric.contains(c.r.model) ? se.add_s_m : se.add_m;
        adds_of[c.r.model].push_back(1e3 * adds);
        if (adds < 0.1 * diagonal.at(c.r.model) && object_points[static_cast<std::size_t>(k)] > 0)
          found_adds[static_cast<std::size_t>(k)] = true;
        else
          ++false_positives_adds;
        accepted_of[static_cast<std::size_t>(k)].push_back({v, PoseHypothesis{c.r.pose, c.r.q_h, 1}});
        if (et < kCorrectM && object_points[static_cast<std::size_t>(k)] > 0) {
          if (!found[static_cast<std::size_t>(k)]) {
            err_mm.push_back(1e3 * et), err_deg.push_back(angle_deg(c.r.pose, truth));
            rot_of[c.r.model].push_back(err_deg.back());
          }
          found[static_cast<std::size_t>(k)] = true;
        } else {
          ++false_positives, ++fp_view;
          std::printf("  FP scene %llu view %2d: %s accepted (q_h %.2f, v_h %.2f) on a cluster of %s, %.0f mm from its "
                      "true pose\n",
                      static_cast<unsigned long long>(scene_seed), v, c.r.model.c_str(), c.r.q_h, c.r.v_h,
                      c.truth >= 0 ? sc.objects[static_cast<std::size_t>(c.truth)].name.c_str() : "?", 1e3 * et);
        }
      }
      fp_per_view.push_back(fp_view);
      int vis_view = 0, rec_view = 0;
      for (std::size_t k = 0; k < sc.objects.size(); ++k) {
        if (object_points[k] < kMinVisiblePoints) continue;
        const std::string& name = sc.objects[k].name;
        ++visible, ++vis_view, ++per_object[name][0];
        if (found_adds[k]) ++recognised_adds;
        if (found[k]) {
          ++recognised, ++rec_view, ++per_object[name][1];
          continue;
        }
        // Why missed: the cluster whose majority this object is (the largest such), and its outcome.
        const ClusterOutcome* own = nullptr;
        for (const ClusterOutcome& c : outcomes)
          if (c.truth == static_cast<int>(k) && (own == nullptr || c.truth_points > own->truth_points)) own = &c;
        Miss why = kNoCluster;
        double et = std::nan("");
        if (own != nullptr) {
          if (own->r.model.empty()) why = kNoHypothesis;
          else if (own->r.model != name) why = kOtherModel;
          else {
            et = position_error(name, own->r.pose, sc.objects[k].T_world_object);
            why = et >= kCorrectM ? kFar : kRejected;
          }
        }
        ++misses[name][why];
        std::printf("  miss scene %llu view %2d: %-8s %5zu points: %s", static_cast<unsigned long long>(scene_seed), v,
                    name.c_str(), object_points[k], kMissNames[why]);
        if (own != nullptr && !own->r.model.empty())
          std::printf(" (best %s q_h %.2f v_h %.2f%s; cluster %zu of its points)", own->r.model.c_str(), own->r.q_h,
                      own->r.v_h, std::isnan(et) ? "" : (", " + std::to_string(std::lround(1e3 * et)) + " mm").c_str(),
                      own->truth_points);
        std::printf("\n");
      }
      std::printf("scene %llu view %2d: eye (%6.3f, %6.3f, %5.3f), %zu clusters, %d of %d visible recognised, %d FP\n",
                  static_cast<unsigned long long>(scene_seed), v, eye.x(), eye.y(), eye.z(), outcomes.size(), rec_view,
                  vis_view, fp_view);
      std::fflush(stdout);
    }
    // Fusion over the views of this scene.
    for (std::size_t k = 0; k < sc.objects.size(); ++k)
      for (const int kv : fusion_k) {
        PoseFusion fusion(fusion_setting);
        for (const Accepted& a : accepted_of[k])
          if (a.view < kv) fusion.add(a.h);
        const std::optional<PoseHypothesis> p = fusion.fused();
        if (!p) continue;
        const std::string& name = sc.objects[k].name;
        const double e_mm = 1e3 * position_error(name, p->pose, sc.objects[k].T_world_object);
        const double e_deg = angle_deg(p->pose, sc.objects[k].T_world_object);
        fused[kv][0].push_back(e_mm), fused[kv][1].push_back(e_deg);
        if (name == "bunny" || name == "mug") fused[kv][2].push_back(e_mm), fused[kv][3].push_back(e_deg);
      }
  }
  std::filesystem::remove_all(db_dir);

  std::printf("\nper object: visible / recognised; misses by reason (%s | %s | %s | %s | %s)\n", kMissNames[0],
              kMissNames[1], kMissNames[2], kMissNames[3], kMissNames[4]);
  for (const auto& [name, vr] : per_object) {
    const auto& m = misses[name];
    std::printf("  %-9s %3d / %3d  misses %d | %d | %d | %d | %d   rotation error median %6.2f deg\n", name.c_str(), vr[0],
                vr[1], m[0], m[1], m[2], m[3], m[4], quantile(rot_of[name], 0.5));
  }
  const double recall = visible > 0 ? static_cast<double>(recognised) / visible : 0.0;
  const double fp_rate = accepted_total > 0 ? static_cast<double>(false_positives) / accepted_total : 0.0;
  std::printf("views %d, visible instances %d (>= %zu object points > 5 mm above the table), recognised within 30 mm "
              "%d (%.1f %%), clusters %d, accepted hypotheses %d, false positives %d (%.1f %% of accepted, %.2f per "
              "view)\n",
              scenes * views, visible, kMinVisiblePoints, recognised, 100.0 * recall, clusters_total, accepted_total,
              false_positives, 100.0 * fp_rate, static_cast<double>(false_positives) / (scenes * views));
  std::printf("records split from a segmentation cluster that held several objects: %d\n", parts_total);
  if (rs.reject_ambiguous)
    std::printf("refused as ambiguous: %d (%d within 30 mm of the truth, %d not)\n", ambiguous_right + ambiguous_wrong,
                ambiguous_right, ambiguous_wrong);
  std::printf("symmetry-aware (ADD-S for mushroom, plate, table, ADD for the others, < 0.1 x model diagonal): recognised %d (%.1f %%), false positives %d (%.1f %% of "
              "accepted)\n",
              recognised_adds, visible > 0 ? 100.0 * recognised_adds / visible : 0.0, false_positives_adds,
              accepted_total > 0 ? 100.0 * false_positives_adds / accepted_total : 0.0);
  for (const auto& [name, v] : adds_of)
    std::printf("  %-9s %-5s of its %3zu accepted: median %6.2f p90 %6.2f max %6.2f mm (criterion 0.1 x box diagonal = %.1f mm)\n",
                name.c_str(), kSymmetric.contains(name) ? "ADD-S" : "ADD", v.size(), quantile(v, 0.5), quantile(v, 0.9),
                quantile(v, 1.0),
                100.0 * diagonal.at(name));
  std::printf("time: %.0f ms per cluster record (recognise_clusters against %zu models)\n",
              clusters_total > 0 ? 1e3 * recognise_s / clusters_total : 0.0, db.models().size());
  std::printf("errors of the recognised instances:\n");
  print_distribution("position", err_mm, "mm");
  print_distribution("rotation", err_deg, "deg");
  std::printf("pose fusion (cut-offs %.0f mm / %.0f deg) of each (scene, object)'s accepted hypotheses in views 1..k:\n",
              1e3 * fusion_setting.max_translation_m, fusion_setting.max_rotation_rad * 180.0 / std::numbers::pi);
  for (const auto& [kv, e] : fused)
    std::printf("  k %2d: all %2zu: position median %6.2f p90 %6.2f mm, rotation median %6.2f p90 %6.2f deg | "
                "bunny+mug %2zu: position median %5.2f p90 %5.2f mm, rotation median %5.2f p90 %5.2f deg\n",
                kv, e[0].size(), quantile(e[0], 0.5), quantile(e[0], 0.9), quantile(e[1], 0.5), quantile(e[1], 0.9),
                e[2].size(), quantile(e[2], 0.5), quantile(e[2], 0.9), quantile(e[3], 0.5), quantile(e[3], 0.9));
  const std::string suffix = close_set ? "_close" : "";
  bench::report_headline("recognition.single_view_recall" + suffix, recall, "recognised within 30 mm / visible instances");
  bench::report_headline("recognition.false_positive_rate" + suffix, fp_rate, "false positives / accepted hypotheses");
  return 0;
}
