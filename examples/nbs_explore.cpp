// SPDX-License-Identifier: BSD-3-Clause
// nbs_explore — active scene exploration (thesis Sec. 3.1, Fig. 3.1; issue 21 item 5) in simulation: a seeded
// table-top scene (nbs/scene/scene_generator.hpp), overview frames of the Asus Xtion preset (Embree), segmentation,
// recognition of every cluster against the model database (PPF voting, q_h, ICP, v_h ≥ 0.66 against the scene's
// voxel space), NBS modeling (method C_H, DLR laser stripe profiler) of each unexplained cluster with its box as
// the unknown area, the new model into the database, re-recognition. Prints one line per step; writes per-object
// meshes (PLY), a picture per step (top view, clusters coloured: recognised green, being modeled yellow, unexplained
// red, modeled but not recognised blue, ambiguous — a known model whose pose the view leaves open, unless
// --accept-ambiguous — light green; table grey) and report.json. Run `nbs_explore --help`.

// Planner headers first (see nbs/planner/detail/components.hpp).
#include "nbs/planner/nbs_planner.hpp"
#include "nbs/planner/simulation_loop.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <numbers>
#include <optional>
#include <sstream>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "nbs/embree/scene.hpp"
#include "nbs/embree/scene_scanner.hpp"
#include "nbs/embree/simulated_scanner.hpp"
#include "nbs/explore/simulated_exploration.hpp"
#include "nbs/io/load_mesh.hpp"
#include "nbs/io/write_json.hpp"
#include "nbs/mesh/conversion.hpp"
#include "nbs/mesh/normalize.hpp"
#include "nbs/mesh/ply.hpp"
#include "nbs/png/write_png.hpp"
#include "nbs/scene/scene_generator.hpp"
#include "nbs/sensor/presets.hpp"
#include "nbs/sim/ground_truth.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"

#include "common/data_dir.hpp"

namespace {

using namespace nbs;
using Space = ProbabilisticVoxelSpace<>;

struct Options {
  std::string scene = "+mug,bunny";
  std::uint64_t seed = 1;
  std::string db;
  std::string out = "nbs_explore_out";
  int scans = 40;         ///< modeling scans over all objects
  int object_scans = 20;  ///< n_abort per object
  int steps = 6;
  unsigned threads = 0;
  double ambiguity_margin = explore::PpfRecogniserSetting{}.ambiguity_margin;  ///< PpfRecogniserSetting's
  bool accept_ambiguous = false;   ///< PpfRecogniserSetting::reject_ambiguous = false (the thesis's recogniser)
  double min_gap = 0.03;           ///< SceneSettings::min_gap_m, m
  std::optional<double> max_gap;   ///< SceneSettings::max_gap_m, m (close scenes)
  bool blind_planner = false;      ///< NbsObjectModeler::predict_occlusion = false (the thesis's planner)
  bool aim = false;                ///< ExplorationSetting::aim_ambiguous: planned recognition views
};

/// One object of --scene: a bundled mesh in its frame (+z up, metres) and whether it is in the database at start.
struct SceneObject {
  scene::ObjectSpec spec;
  bool known = false;
};

IndexedMesh bundled_mesh(const std::string& name) {
  if (name == "bunny") {
    IndexedMesh m = load_mesh(tools::bundled_data("meshes/stanford-bunny.obj"));
    normalize_on_pedestal(m, 0.16, UpAxis::y);
    return m;
  }
  for (const char* n : {"table", "car", "mug", "mushroom", "plate"})
    if (name == n) return load_mesh(tools::bundled_data("meshes/test-objects/" + name + ".obj"));
  throw InvalidArgument("--scene: unknown object '" + name + "' (bunny, table, car, mug, mushroom, plate)");
}

std::vector<SceneObject> parse_scene(const std::string& spec) {
  std::vector<SceneObject> out;
  std::stringstream ss(spec);
  std::string item;
  while (std::getline(ss, item, ',')) {
    SceneObject o;
    o.known = !item.empty() && item.front() == '+';
    const std::string name = o.known ? item.substr(1) : item;
    for (const SceneObject& p : out)
      if (p.spec.name == name) throw InvalidArgument("--scene: object '" + name + "' is given twice");
    o.spec = {name, bundled_mesh(name)};
    out.push_back(std::move(o));
  }
  if (out.empty()) throw InvalidArgument("--scene: no objects in '" + spec + "'");
  return out;
}

/// Top view of the frame's points (0.8 × 0.6 m table, 1 px = 1 mm), coloured by cluster state.
void write_step_picture(const std::string& path, const Scan& frame, const scene::SceneSettings& st,
                        const explore::StepRecord& rec) {
  const auto w = static_cast<std::uint32_t>(std::lround(st.table_size_x_m * 1000)),
             h = static_cast<std::uint32_t>(std::lround(st.table_size_y_m * 1000));
  std::vector<std::uint8_t> rgb(std::size_t{w} * h * 3, 255);
  const auto put = [&](const Vec3& p, std::array<std::uint8_t, 3> c) {
    const long u = std::lround((p.x() + 0.5 * st.table_size_x_m) * 1000), v = std::lround((0.5 * st.table_size_y_m - p.y()) * 1000);
    for (long dv = -1; dv <= 1; ++dv)
      for (long du = -1; du <= 1; ++du) {
        const long x = u + du, y = v + dv;
        if (x < 0 || y < 0 || x >= long(w) || y >= long(h)) continue;
        std::copy(c.begin(), c.end(), rgb.begin() + (std::size_t(y) * w + std::size_t(x)) * 3);
      }
  };
  for (const Vec3& p : frame.points) put(p, {170, 170, 170});
  for (const explore::ClusterRecord& cluster : rec.clusters) {
    std::array<std::uint8_t, 3> c{220, 30, 30};
    switch (cluster.state) {
      case explore::ClusterState::recognised: c = {30, 170, 30}; break;
      case explore::ClusterState::modeling: c = {235, 200, 0}; break;
      case explore::ClusterState::modeled: c = {40, 80, 220}; break;
      case explore::ClusterState::ambiguous: c = {150, 210, 90}; break;
      case explore::ClusterState::unexplained: break;
    }
    for (const std::size_t i : cluster.indices) put(frame.points[i], c);
  }
  png::write_png(path, w, h, rgb);
}

double angle_deg(const Pose& a, const Pose& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() * 180.0 / std::numbers::pi;
}

int run(const Options& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<SceneObject> objects;
  try {
    objects = parse_scene(opt.scene);
  } catch (const Error& e) {
    std::cerr << "nbs_explore: " << e.what() << "\n";
    return 2;
  }
  std::filesystem::create_directories(opt.out);
  const std::string db_dir = opt.db.empty() ? (std::filesystem::path(opt.out) / "db").string() : opt.db;
  ModelDatabase db = ModelDatabase::create(db_dir);

  std::vector<scene::ObjectSpec> specs;
  for (const SceneObject& o : objects) specs.push_back(o.spec);
  scene::SceneSettings st;
  st.min_gap_m = opt.min_gap;
  st.max_gap_m = opt.max_gap;
  st.table_size_x_m = 0.6;
  st.table_size_y_m = 0.45;
  const scene::SimulatedScene sc = scene::generate_scene(specs, st, opt.seed);
  const embree::SceneScanner overview_scanner(sc);
  IndexedMesh only_objects;
  for (const auto& o : sc.objects) {
    const auto base = static_cast<std::uint32_t>(only_objects.vertices.size());
    only_objects.vertices.insert(only_objects.vertices.end(), o.mesh.vertices.begin(), o.mesh.vertices.end());
    for (const auto& t : o.mesh.triangles) only_objects.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  }
  const embree::SimulatedScanner model_scanner(only_objects, embree::ScannerSettings{.pedestal_top_z_m = st.table_height_m,
                                                                                    .ray_mode = embree::RayMode::packet});
  Space space(0.005, Aabb{Vec3(-0.5 * st.table_size_x_m, -0.5 * st.table_size_y_m, st.table_height_m - 0.01),
                          Vec3(0.5 * st.table_size_x_m, 0.5 * st.table_size_y_m, st.table_height_m + 0.3)});

  explore::PpfRecogniserSetting rs;
  rs.seed = opt.seed;
  rs.threads = opt.threads;
  rs.reject_ambiguous = !opt.accept_ambiguous;
  rs.ambiguity_margin = opt.ambiguity_margin;
  for (const SceneObject& o : objects)
    if (o.known && !db.find(o.spec.name))
      db.add({o.spec.name, 0.0, {}, {"bundled mesh"}}, o.spec.mesh,
             PpfModel(oriented_points(sample_surface(o.spec.mesh, rs.surface_samples, rs.seed)), rs.model));
  std::printf("scene   seed %llu: ", static_cast<unsigned long long>(opt.seed));
  for (std::size_t k = 0; k < sc.objects.size(); ++k)
    std::printf("%s%s at (%.3f, %.3f)%s", k ? ", " : "", sc.objects[k].name.c_str(),
                sc.objects[k].T_world_object.translation().x(), sc.objects[k].T_world_object.translation().y(),
                objects[k].known ? " [in db]" : "");
  std::printf("\ndb      %s: %zu models\n", db_dir.c_str(), db.models().size());

  const AreaSensor xtion = presets::asus_xtion_pro();
  explore::PpfRecogniser<embree::Scene, Space> recogniser(db, xtion, space, rs);
  explore::OverviewRingSetting ring;
  ring.target = Vec3(0.0, 0.0, st.table_height_m + 0.05);
  explore::RecognitionViewSetting aim;
  aim.threads = opt.threads > 0 ? opt.threads : std::max(1U, std::thread::hardware_concurrency());
  explore::OverviewRing<embree::SimulatedScanner, Space> source{&overview_scanner.scanner(), xtion, &space, ring, opt.seed,
                                                                aim, std::nullopt, opt.threads};
  explore::NbsObjectModeler<embree::SimulatedScanner, Space> modeler{&model_scanner, &space, opt.object_scans, opt.seed,
                                                                     opt.threads, {}, 0, !opt.blind_planner};
  explore::ExplorationSetting es;
  es.scan_budget = opt.scans;
  es.max_steps = opt.steps;
  es.aim_ambiguous = opt.aim;
  for (int run = 1;; ++run) {  // a prefix no model in the database has (a database reused across runs)
    es.name_prefix = "run" + std::to_string(run) + "_object_";
    if (std::none_of(db.models().begin(), db.models().end(),
                     [&](const DatabaseModel& m) { return m.metadata.name.rfind(es.name_prefix, 0) == 0; }))
      break;
  }

  // Ground truth of a cluster of `frame`: the object most of its points are nearest to.
  // The scene objects a cluster's points hit (simulation truth): the one with most points, and every object with at
  // least 10 % of them (two or more: one cluster holds touching objects, which the loop models as one).
  struct Truth {
    int best = -1;
    std::vector<int> objects;
  };
  const auto truth_objects = [&](const explore::ClusterRecord& c, const Scan& frame) {
    std::vector<Vec3> pts;
    for (const std::size_t i : c.indices) pts.push_back(frame.points[i]);
    const std::vector<int> labels = overview_scanner.labels(pts, opt.threads);
    std::map<int, std::size_t> votes;
    for (int l : labels) ++votes[l];
    Truth t;
    std::size_t n = 0;
    for (auto [l, count] : votes) {
      if (l < 0) continue;
      if (count > n) t.best = l, n = count;
      if (10 * count >= labels.size()) t.objects.push_back(l);
    }
    return t;
  };
  const auto names_of = [&](const std::vector<int>& objects) {
    nlohmann::ordered_json names = nlohmann::json::array();
    std::string joined;
    for (int l : objects) {
      names.push_back(sc.objects[std::size_t(l)].name);
      joined += (joined.empty() ? "" : " + ") + sc.objects[std::size_t(l)].name;
    }
    return std::pair{names, joined};
  };
  // Where a model's frame is in the world: the database models of the scene objects at T_world_object, learned
  // models where they were modeled.
  std::map<std::string, Pose> truth_pose;
  std::map<std::string, int> learned_object;
  for (std::size_t k = 0; k < sc.objects.size(); ++k) truth_pose[sc.objects[k].name] = sc.objects[k].T_world_object;

  nlohmann::ordered_json jsteps = nlohmann::json::array();
  std::printf("step  view (x, y, z) m          clusters  recognised (q_h / v_h, error mm / deg)   modeling (ĉ_m, scans)\n");
  Scan last_frame;
  const auto record = [&](const explore::StepRecord& rec) {
    nlohmann::ordered_json js;
    js["step"] = rec.step;
    const Vec3 v = rec.view.translation();
    js["view"] = {v.x(), v.y(), v.z()};
    js["frame_points"] = rec.frame_points;
    js["aimed_at"] = rec.aimed_at;
    std::ostringstream line;
    char buf[256];
    std::snprintf(buf, sizeof buf, "%4d  (%6.3f, %6.3f, %5.3f)  %8zu ", rec.step, v.x(), v.y(), v.z(), rec.clusters.size());
    line << buf;
    if (source.last_aimed) {
      const explore::RecognitionView& a = *source.last_aimed;
      js["aimed_view"] = {{"azimuth_deg", a.azimuth_rad * 180.0 / std::numbers::pi},
                          {"elevation_deg", a.elevation_rad * 180.0 / std::numbers::pi},
                          {"unobserved_voxels", a.score}};
      std::snprintf(buf, sizeof buf, "[aimed at %d ambiguous: az %.0f el %.0f deg, %.0f unobserved voxels]  ",
                    rec.aimed_at, a.azimuth_rad * 180.0 / std::numbers::pi, a.elevation_rad * 180.0 / std::numbers::pi,
                    a.score);
      line << buf;
    }
    nlohmann::ordered_json jc = nlohmann::json::array();
    std::vector<Truth> truths;  // per cluster, once: the modeled cluster's too
    for (const explore::ClusterRecord& c : rec.clusters) truths.push_back(truth_objects(c, last_frame));
    for (std::size_t k = 0; k < rec.clusters.size(); ++k) {
      const explore::ClusterRecord& c = rec.clusters[k];
      nlohmann::ordered_json o;
      const Truth& tr = truths[k];
      const int truth = tr.best;
      const auto [held, held_line] = names_of(tr.objects);
      o["state"] = explore::to_string(c.state);
      o["points"] = c.points;
      o["truth_object"] = truth >= 0 ? sc.objects[std::size_t(truth)].name : std::string();
      o["truth_objects"] = held;  // ≥ 2: the cluster holds touching objects (each ≥ 10 % of its points)
      o["model"] = c.recognition.model;
      o["q_h"] = c.recognition.q_h;
      o["v_h"] = c.recognition.v_h;
      o["ambiguous"] = c.recognition.ambiguous;
      o["segment"] = c.segment;  // records sharing it are pieces of one segmentation cluster
      o["split"] = c.split;      // a piece of a cluster that held a recognised object and more
      o["remembered"] = c.remembered;  // ambiguous in this view, recognised at an earlier step's placement
      o["q_h_alternative"] = c.recognition.q_h_alternative;
      o["box_min"] = {c.box.min.x(), c.box.min.y(), c.box.min.z()};
      o["box_max"] = {c.box.max.x(), c.box.max.y(), c.box.max.z()};
      std::string errors;
      if (c.state == explore::ClusterState::recognised) {
        // The error is defined when the recognised model is the cluster's true object (or was modeled from it).
        const auto it = truth_pose.find(c.recognition.model);
        const bool same = truth >= 0 && (c.recognition.model == sc.objects[std::size_t(truth)].name ||
                                         (learned_object.count(c.recognition.model) &&
                                          learned_object[c.recognition.model] == truth));
        if (it != truth_pose.end() && same) {
          const double et = (c.recognition.pose.translation() - it->second.translation()).norm();
          const double er = angle_deg(c.recognition.pose, it->second);
          o["error_mm"] = 1e3 * et;
          o["error_deg"] = er;
          std::snprintf(buf, sizeof buf, ", %.1f mm / %.1f deg", 1e3 * et, er);
          errors = buf;
        } else {
          o["false_positive"] = true;
          errors = ", WRONG OBJECT";
        }
        std::snprintf(buf, sizeof buf, "  %s (%.2f / %.2f%s)", c.recognition.model.c_str(), c.recognition.q_h,
                      c.recognition.v_h, errors.c_str());
        line << buf;
      } else {
        std::snprintf(buf, sizeof buf, "  [%s: best %s q_h %.2f v_h %.2f]", explore::to_string(c.state),
                      c.recognition.model.empty() ? "-" : c.recognition.model.c_str(), c.recognition.q_h, c.recognition.v_h);
        line << buf;
      }
      if (c.remembered) line << " (remembered)";
      if (c.split) line << " (split segment " << c.segment << ")";
      if (tr.objects.size() > 1) line << " (holds " << held_line << ")";
      jc.push_back(o);
    }
    js["clusters"] = jc;
    if (rec.learned) {
      const explore::LearnedModel& m = *rec.learned;
      const Truth& tr = truths[std::size_t(rec.modeled_cluster)];
      const int truth = tr.best;
      const auto [held, held_line] = names_of(tr.objects);
      nlohmann::ordered_json jm;
      jm["name"] = m.name;
      jm["truth_object"] = truth >= 0 ? sc.objects[std::size_t(truth)].name : std::string();
      jm["truth_objects"] = held;  // ≥ 2: touching objects modeled as one (c_a is against truth_object)
      jm["estimated_coverage"] = m.coverage;
      jm["scans"] = m.scans;
      jm["done"] = m.done;
      double c_a = 0.0;
      if (truth >= 0 && !m.mesh_world.vertices.empty()) {
        GroundTruth::Setting gs;
        gs.seed = opt.seed;
        gs.bottom.pedestal_z_m = st.table_height_m;
        const GroundTruth gt(sc.objects[std::size_t(truth)].mesh, gs);
        c_a = gt.completeness(m.mesh_world.vertices, opt.threads).c_a();
        jm["c_a"] = c_a;
        jm["e_rms_mm"] = 1e3 * gt.rms_error(m.mesh_world.vertices, opt.threads);
      }
      if (!m.name.empty()) {
        truth_pose[m.name] = m.T_world_model;
        learned_object[m.name] = truth;
        write_mesh_ply((std::filesystem::path(opt.out) / (m.name + ".ply")).string(), m.mesh_world);
      }
      std::snprintf(buf, sizeof buf, "  -> modeled %s (%s): ĉ_m %.3f, %d scans%s, c_a %.1f %%", m.name.c_str(),
                    truth >= 0 ? sc.objects[std::size_t(truth)].name.c_str() : "?", m.coverage, m.scans,
                    m.done ? "" : " (not done)", 100.0 * c_a);
      line << buf;
      if (tr.objects.size() > 1) line << " (one model of " << held_line << ": they touch)";
      js["modeled"] = jm;
    }
    char name[64];
    std::snprintf(name, sizeof name, "step_%02d.png", rec.step);
    write_step_picture((std::filesystem::path(opt.out) / name).string(), last_frame, st, rec);
    jsteps.push_back(js);
    std::printf("%s\n", line.str().c_str());
    std::fflush(stdout);
  };
  // The source wrapped so that the step callback sees the frame the step segmented.
  struct Remember {
    explore::OverviewRing<embree::SimulatedScanner, Space>* s;
    Scan* last;
    Scan overview(int step) {
      *last = s->overview(step);
      return *last;
    }
    Scan overview(int step, std::span<const Aabb> boxes) {
      *last = s->overview(step, boxes);
      return *last;
    }
  } remember{&source, &last_frame};
  const explore::ExplorationResult r = explore::explore_scene(remember, recogniser, modeler, es, record);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("stop    %s after %zu steps, %d modeling scans, %zu models learned, db %zu models; wall %.1f s\n",
              explore::to_string(r.stop), r.steps.size(), r.scans, r.learned.size(), db.models().size(), wall);
  nlohmann::ordered_json j;
  j["scene"] = opt.scene;
  j["seed"] = opt.seed;
  j["predict_occlusion"] = !opt.blind_planner;
  j["planned_recognition_views"] = opt.aim;
  j["db"] = db_dir;
  nlohmann::ordered_json jo = nlohmann::json::array();
  for (std::size_t k = 0; k < sc.objects.size(); ++k) {
    const Vec3 t = sc.objects[k].T_world_object.translation();
    jo.push_back({{"name", sc.objects[k].name}, {"in_db_at_start", objects[k].known}, {"position", {t.x(), t.y(), t.z()}}});
  }
  j["objects"] = jo;
  j["steps"] = jsteps;
  j["stop"] = explore::to_string(r.stop);
  j["modeling_scans"] = r.scans;
  j["wall_s"] = wall;
  write_json((std::filesystem::path(opt.out) / "report.json").string(), j);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options opt;
  CLI::App app("nbs_explore: simulated active scene exploration (recognise known objects, model unknown ones)",
               "nbs_explore");
  app.add_option("--scene", opt.scene,
                 "comma-separated objects (bunny, table, car, mug, mushroom, plate); '+name': in the database at start")
      ->capture_default_str();
  app.add_option("--seed", opt.seed, "scene, noise and sampling seed")->capture_default_str();
  app.add_option("--db", opt.db, "model database directory (created if missing; default OUT/db)");
  app.add_option("--out", opt.out, "output directory")->capture_default_str();
  app.add_option("--scans", opt.scans, "modeling scans over all objects")->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--object-scans", opt.object_scans, "n_abort per modeled object")->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--steps", opt.steps, "most overview steps")->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--threads", opt.threads, "threads (0: all)")->capture_default_str();
  app.add_option("--ambiguity-margin", opt.ambiguity_margin,
                 "refuse a recognition another placement of the model explains within this q_h margin (the cluster "
                 "is then 'ambiguous': not modeled, and further overviews are taken)")
      ->capture_default_str()->check(CLI::NonNegativeNumber);
  app.add_option("--min-gap", opt.min_gap, "least distance between the objects' footprints, m (0: they may touch)")
      ->capture_default_str()->check(CLI::NonNegativeNumber);
  app.add_option("--max-gap", opt.max_gap,
                 "place every object after the first within this distance of a placed one, m, >= --min-gap (close scenes)")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--accept-ambiguous", opt.accept_ambiguous,
               "accept the best placement even when another explains the view as well (the thesis's recogniser)");
  app.add_flag("--aim", opt.aim,
               "aim the overview after a step with ambiguous clusters at them (planned recognition views; else the ring)");
  app.add_flag("--blind-planner", opt.blind_planner,
               "the modeling planner does not predict occlusion by the other objects (sees only its box, as the thesis's)");
  app.footer("Writes OUT/<model>.ply (learned models, world frame), OUT/step_NN.png and OUT/report.json.");
  CLI11_PARSE(app, argc, argv);
  try {
    return run(opt);
  } catch (const nbs::Error& e) {
    std::cerr << "nbs_explore: " << e.what() << "\n";
    return 1;
  }
}
