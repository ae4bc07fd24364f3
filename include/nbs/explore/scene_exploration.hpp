// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The scene-exploration loop of the thesis (Sec. 3.1, Fig. 3.1; issue 21 item 5): overview frame → segmentation →
/// recognition of every cluster against the model database → NBS modeling of one unexplained cluster (its box is the
/// unknown area) → the new model into the database → next step (a new overview, everything re-recognised), until
/// every cluster is explained, the scan budget is spent or the step limit is reached.
///
/// The loop is generic over three concepts: an `OverviewSource` (the area-sensor frames), an `ObjectRecogniser`
/// (recognise a cluster, learn a new model) and an `ObjectModeler` (NBS modeling of one box). `PpfRecogniser`
/// (recognition/ of this library: PPF voting, q_h, ICP, v_h against a voxel space, a `ModelDatabase`) is the
/// recogniser of the thesis; the Embree wiring of the source and the modeler is in examples/nbs_explore.cpp.
/// World frame, metres, radians.

#include <algorithm>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <numeric>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/core/scan.hpp"
#include "nbs/explore/cluster_recognition.hpp"
#include "nbs/mesh/indexed_mesh.hpp"
#include "nbs/recognition/hypothesis_validation.hpp"
#include "nbs/recognition/hypothesis_verification.hpp"
#include "nbs/recognition/model_database.hpp"
#include "nbs/recognition/pose_surface_error.hpp"
#include "nbs/recognition/ppf_match.hpp"
#include "nbs/recognition/refine_pose.hpp"
#include "nbs/registration/scan_normals.hpp"
#include "nbs/scene/segmentation.hpp"
#include "nbs/sensor/area_sensor.hpp"
#include "nbs/sim/ray_caster.hpp"
#include "nbs/sim/surface_samples.hpp"

namespace nbs::explore {

/// The outcome of NBS modeling of one cluster.
struct ModelingResult {
  IndexedMesh mesh;       ///< the model, world frame
  double coverage = 0.0;  ///< ĉ_m after the last scan
  int scans = 0;          ///< scans taken
  bool done = false;      ///< the termination criterion was reached (else: scan budget or no candidates)
};

/// The overview frames: `overview(step)` is the area-sensor frame of step `step` (0-based; the source chooses the
/// view, and feeds the frame into whatever voxel space its recogniser validates against).
template <class S>
concept OverviewSource = requires(S& s, int step) {
  { s.overview(step) } -> std::same_as<Scan>;
};

/// Capability of an OverviewSource: `overview(step, boxes)` plans the frame of step `step` to show the boxes (world
/// frame) of the clusters the last step left ambiguous (Sec. 3.1's planned recognition views); the loop calls it
/// instead of `overview(step)` when there are such boxes and ExplorationSetting::aim_ambiguous is set.
template <class S>
concept AimedOverviewSource = OverviewSource<S> && requires(S& s, int step, std::span<const Aabb> boxes) {
  { s.overview(step, boxes) } -> std::same_as<Scan>;
};

/// NBS modeling of the object in `hypothesis.box` with at most `max_scans` scans (≥ 1).
template <class M>
concept ObjectModeler = requires(M& m, const scene::ObjectHypothesis& h, int max_scans) {
  { m.model(h, max_scans) } -> std::same_as<ModelingResult>;
};

/// A model the loop made of one cluster. Learned (added to the recogniser under `name`) only if its mesh has a
/// triangle; else `name` is empty and the entry only keeps its box from being modeled again.
struct LearnedModel {
  std::string name;                       ///< empty: the mesh came out empty, not learned
  Pose T_world_model = Pose::Identity();  ///< the model frame: a translation to the box's bottom centre
  IndexedMesh mesh_world;                 ///< as modeled (world frame)
  Aabb box;                               ///< the cluster's box it was modeled in
  double coverage = 0.0;                  ///< ĉ_m at the end of its modeling
  int scans = 0;
  bool done = false;
};

/// One step of the loop.
struct StepRecord {
  int step = 0;                          ///< 0-based
  Pose view = Pose::Identity();          ///< T_WS of the overview frame
  /// Ambiguous clusters of the previous step the frame was aimed at (AimedOverviewSource); 0: the source's own view
  int aimed_at = 0;
  std::size_t frame_points = 0;
  scene::SegmentationStatus segmentation = scene::SegmentationStatus::ok;
  std::vector<ClusterRecord> clusters;
  int modeled_cluster = -1;              ///< index into clusters of the object modeled in this step, −1: none
  std::optional<LearnedModel> learned;   ///< its model (also when the mesh came out empty: then not learned)
};

enum class ExplorationStop : std::uint8_t { explained, scan_budget, max_steps, no_plane };

[[nodiscard]] inline const char* to_string(ExplorationStop s) {
  switch (s) {
    case ExplorationStop::explained: return "explained";
    case ExplorationStop::scan_budget: return "scan_budget";
    case ExplorationStop::max_steps: return "max_steps";
    case ExplorationStop::no_plane: return "no_plane";
  }
  return "?";
}

struct ExplorationSetting {
  scene::SegmentationSettings segmentation;
  int scan_budget = 60;                 ///< modeling scans over all objects, ≥ 1
  int max_steps = 8;                    ///< overview steps, ≥ 1
  std::string name_prefix = "object_";  ///< learned models are named prefix + 1, 2, … in learning order
  /// Take further overviews (up to max_steps) while a cluster is ambiguous, so that another view can tell its pose;
  /// false: an ambiguous cluster does not keep the loop from stopping as explained.
  bool resolve_ambiguous = true;
  /// Splits of one segmentation cluster (touching objects form one cluster) with a recogniser that models
  /// PartRecogniser (see recognise_clusters), ≥ 0; 0: one object per cluster, as the thesis.
  int max_parts = 3;
  /// A cluster a view leaves ambiguous whose box holds the centroid of a cluster recognised unambiguously as the
  /// same model in an earlier step (newest first; not inside the box of an object the loop modeled, and until a
  /// later step sees something else there) is recognised at that placement (`ClusterRecord::remembered`): a view
  /// that hides the telling part again does not undo what an earlier view told. false: every step on its own.
  bool remember_recognitions = true;
  /// ... and whose best placement in this view lies within this distance of the earlier one (model frame origins,
  /// metres, ≥ 0; the recognition evaluation's 30 mm): the same object, its pose only open in this view.
  double remember_distance_m = 0.03;
  /// With an AimedOverviewSource: aim the next overview at the clusters a step left ambiguous (planned recognition
  /// views). Off by default: the view that sees most of a box's unobserved voxels did not tell poses apart better
  /// than the ring's next view on the development scenes, and a wrong model's ambiguity (the mushroom as the plate)
  /// then persists instead of the cluster being modeled (docs/evaluation.md, "Planned recognition views").
  bool aim_ambiguous = false;

  void validate() const {
    segmentation.validate();
    detail::require(scan_budget >= 1, "ExplorationSetting.scan_budget must be >= 1, got ", scan_budget);
    detail::require(max_steps >= 1, "ExplorationSetting.max_steps must be >= 1, got ", max_steps);
    detail::require(max_parts >= 0, "ExplorationSetting.max_parts must be >= 0, got ", max_parts);
    detail::require_non_negative("ExplorationSetting.remember_distance_m", remember_distance_m);
  }
};

struct ExplorationResult {
  std::vector<StepRecord> steps;
  std::vector<LearnedModel> learned;  ///< every modeled cluster in modeling order, also the unlearned (empty name)
  int scans = 0;  ///< modeling scans taken
  ExplorationStop stop = ExplorationStop::max_steps;
};

/// Runs the loop. Per step: `source.overview(step)` (with `aim_ambiguous` and an AimedOverviewSource:
/// `source.overview(step, boxes)` while the last step left clusters ambiguous, their boxes), `segment_scene`,
/// `recognise_clusters` (every cluster recognised; with a PartRecogniser, a cluster that holds a known object and
/// more is split, up to `max_parts`; with `remember_recognitions` an ambiguous cluster holding an earlier step's
/// unambiguous placement of its model is recognised there, `remembered`); the first cluster (in segmentation order)
/// that is neither recognised, nor ambiguous (a known model whose pose the view leaves open: not modeled), nor
/// inside the box of an object modeled before (also when ambiguous: `modeled`), nor a split piece of a cluster in
/// which a model the loop learned was recognised (`modeled`: the rest of that object's partial model) is
/// modeled with the scans left, its mesh (if it has a triangle) learned as `name_prefix + k` in a model frame
/// translated to its box's bottom centre; the next step re-recognises everything. Stops when no cluster is left to
/// model and (with `resolve_ambiguous`) none is ambiguous (explained), when the budget is spent before a cluster
/// could be modeled, after `max_steps` steps (also while a cluster stays ambiguous), or when a frame has no support
/// plane. `on_step(record)` is called after each step. Throws InvalidArgument for an invalid
/// setting, a frame with points but no profile pose, or a modeler reporting scans outside [0, its max_scans], and
/// what recognise_clusters, the source, recogniser or modeler throw.
template <OverviewSource Source, ObjectRecogniser Recogniser, ObjectModeler Modeler, class OnStep>
ExplorationResult explore_scene(Source& source, Recogniser& recogniser, Modeler& modeler,
                                const ExplorationSetting& setting, OnStep&& on_step) {
  setting.validate();
  ExplorationResult out;
  int next_name = 1;
  std::vector<Aabb> ambiguous_boxes;  // of the last step's ambiguous clusters
  struct Placement {
    std::string model;
    Pose pose;
    Vec3 centroid;
  };
  std::vector<Placement> placements;  // unambiguous recognitions of earlier steps, newest first
  for (int step = 0; step < setting.max_steps; ++step) {
    int aimed_at = 0;
    Scan frame;
    if constexpr (AimedOverviewSource<Source>) {
      if (setting.aim_ambiguous && !ambiguous_boxes.empty()) {
        frame = source.overview(step, std::span<const Aabb>(ambiguous_boxes));
        aimed_at = static_cast<int>(ambiguous_boxes.size());
      } else {
        frame = source.overview(step);
      }
    } else {
      frame = source.overview(step);
    }
    detail::require(frame.empty() || !frame.profile_poses.empty(), "explore_scene: the overview frame of step ", step,
                    " has ", frame.size(), " points but no profile pose");
    StepRecord rec;
    rec.step = step;
    rec.aimed_at = aimed_at;
    rec.view = frame.profile_poses.empty() ? Pose::Identity() : frame.profile_poses.front();
    rec.frame_points = frame.size();
    const scene::Segmentation seg = scene::segment_scene(frame.points, setting.segmentation);
    rec.segmentation = seg.status;
    if (seg.status != scene::SegmentationStatus::ok) {
      out.steps.push_back(std::move(rec));
      on_step(out.steps.back());
      out.stop = ExplorationStop::no_plane;
      return out;
    }
    std::vector<scene::ObjectHypothesis> hypotheses;  // parallel to rec.clusters
    std::vector<RecognisedCluster> recognised =
        recognise_clusters(recogniser, frame, seg, setting.segmentation, setting.max_parts);
    const auto in_learned_box = [&](const Vec3& x) {
      return std::any_of(out.learned.begin(), out.learned.end(), [&](const LearnedModel& m) { return m.box.contains(x); });
    };
    // Remembered placements first (a remembered learned model marks its segment below); never where an object was
    // modeled before (the `modeled` rule below wins there).
    if (setting.remember_recognitions)
      for (RecognisedCluster& c : recognised) {
        const Recognition& r = c.record.recognition;
        if (c.record.state != ClusterState::ambiguous || r.model.empty() || in_learned_box(c.record.centroid)) continue;
        const auto earlier = std::find_if(placements.begin(), placements.end(), [&](const Placement& p) {
          return p.model == r.model && c.record.box.contains(p.centroid) &&
                 (p.pose.translation() - r.pose.translation()).norm() <= setting.remember_distance_m;
        });
        if (earlier != placements.end()) {
          c.record.state = ClusterState::recognised;
          c.record.remembered = true;
          c.record.recognition.pose = earlier->pose;
        }
      }
    // Segments in which a model the loop learned was recognised: its model is partial (ĉ_m < 1), so the pieces of
    // the segment it leaves are most likely the unmodeled rest of that object, not a new one.
    std::vector<int> learned_segments;
    for (const RecognisedCluster& c : recognised)
      if (c.record.state == ClusterState::recognised &&
          std::any_of(out.learned.begin(), out.learned.end(),
                      [&](const LearnedModel& m) { return !m.name.empty() && m.name == c.record.recognition.model; }))
        learned_segments.push_back(c.record.segment);
    for (RecognisedCluster& c : recognised) {
      const bool rest_of_learned =
          c.record.split && std::find(learned_segments.begin(), learned_segments.end(), c.record.segment) !=
                                learned_segments.end();
      // Modeled before: also when a database model fits it ambiguously (the mushroom's cap fits the plate's two
      // placements alike): that test cannot tell a wrong model, and this object has been modeled.
      if ((c.record.state == ClusterState::unexplained || c.record.state == ClusterState::ambiguous) &&
          (rest_of_learned || in_learned_box(c.record.centroid)))
        c.record.state = ClusterState::modeled;
      rec.clusters.push_back(std::move(c.record));
      hypotheses.push_back(std::move(c.hypothesis));
    }
    const auto todo = std::find_if(rec.clusters.begin(), rec.clusters.end(),
                                   [](const ClusterRecord& c) { return c.state == ClusterState::unexplained; });
    const bool budget_left = out.scans < setting.scan_budget;
    if (todo != rec.clusters.end() && budget_left) {
      const auto k = static_cast<std::size_t>(todo - rec.clusters.begin());
      rec.modeled_cluster = static_cast<int>(k);
      todo->state = ClusterState::modeling;
      const int budget = setting.scan_budget - out.scans;
      ModelingResult m = modeler.model(hypotheses[k], budget);
      detail::require(m.scans >= 0 && m.scans <= budget, "explore_scene: the modeler reported ", m.scans,
                      " scans, outside [0, ", budget, "] (its max_scans)");
      out.scans += m.scans;
      LearnedModel learned;
      learned.box = hypotheses[k].box;
      learned.T_world_model = Pose(Eigen::Translation3d(learned.box.center().x(), learned.box.center().y(),
                                                        learned.box.min.z()));
      learned.coverage = m.coverage;
      learned.scans = m.scans;
      learned.done = m.done;
      learned.mesh_world = std::move(m.mesh);
      if (!learned.mesh_world.triangles.empty()) {
        learned.name = setting.name_prefix + std::to_string(next_name++);
        IndexedMesh local = learned.mesh_world;
        const Pose t_mw = learned.T_world_model.inverse();
        for (Vec3& v : local.vertices) v = t_mw * v;
        for (Vec3& n : local.normals) n = t_mw.linear() * n;
        recogniser.learn(learned.name, local);
      }
      out.learned.push_back(learned);
      rec.learned = std::move(learned);
    }
    const bool modeled = rec.modeled_cluster >= 0, unexplained_left = todo != rec.clusters.end();
    ambiguous_boxes.clear();
    // A placement expires when something else is seen where it was: a cluster there that is neither ambiguous nor
    // recognised as the same model.
    std::erase_if(placements, [&](const Placement& p) {
      return std::any_of(rec.clusters.begin(), rec.clusters.end(), [&](const ClusterRecord& c) {
        return c.box.contains(p.centroid) && c.state != ClusterState::ambiguous &&
               !(c.state == ClusterState::recognised && c.recognition.model == p.model);
      });
    });
    for (const ClusterRecord& c : rec.clusters) {
      if (c.state == ClusterState::ambiguous) ambiguous_boxes.push_back(c.box);
      if (c.state == ClusterState::recognised && !c.remembered)
        placements.insert(placements.begin(), Placement{c.recognition.model, c.recognition.pose, c.centroid});
    }
    const bool ambiguous_left = !ambiguous_boxes.empty();
    out.steps.push_back(std::move(rec));
    on_step(out.steps.back());
    if (!modeled && unexplained_left) {
      out.stop = ExplorationStop::scan_budget;
      return out;
    }
    if (!modeled && !(ambiguous_left && setting.resolve_ambiguous)) {
      out.stop = ExplorationStop::explained;
      return out;
    }
  }
  out.stop = ExplorationStop::max_steps;
  return out;
}

/// explore_scene without a step callback.
template <OverviewSource Source, ObjectRecogniser Recogniser, ObjectModeler Modeler>
ExplorationResult explore_scene(Source& source, Recogniser& recogniser, Modeler& modeler,
                                const ExplorationSetting& setting = {}) {
  return explore_scene(source, recogniser, modeler, setting, [](const StepRecord&) {});
}

/// Settings of PpfRecogniser.
struct PpfRecogniserSetting {
  PpfModelSetting model;                    ///< for the feature tables of learned models
  PpfMatchSetting match;
  std::size_t surface_samples = 20000;      ///< samples of a model's surface (its PPF table and ICP target)
  std::size_t validation_vertices = 4000;   ///< of them, the first n are the vertices of v_h
  std::uint64_t seed = 1;                   ///< surface sampling
  double normal_radius_m = 0.006;           ///< scan normals of the cluster (estimate_scan_normals)
  double tolerance_m = 0.005;               ///< depth tolerance of q_h
  double min_q_h = 0.3;                     ///< least q_h of an accepted hypothesis
  double min_v_h = 0.66;                    ///< least v_h (thesis: 0.66)
  unsigned threads = 1;                     ///< rendering threads (the result does not depend on them)
  /// Refuse an accepted hypothesis when another placement of the same model explains the view as well (the mug
  /// with its handle hidden): see Recognition::ambiguous. The thesis has no such test (false: its recogniser).
  bool reject_ambiguous = true;
  /// q_h difference within which two placements count as equally good, ≥ 0 (chosen on development scenes,
  /// docs/evaluation.md "Symmetry-aware error and ambiguous poses")
  double ambiguity_margin = 0.1;
  /// ADD-S max (× the model's bounding-box diagonal) from which two placements differ, > 0. The max, not the mean:
  /// a turned handle moves a few percent of the surface, which the mean dilutes below any useful bound.
  double ambiguity_distance = 0.1;
  /// recognise_part: the models (best q_h first) whose best hypothesis crops a cluster that is not recognised as a
  /// whole; 0: no parts (recognise_part is recognise(), no crop check of an accepted whole)
  std::size_t part_models = 2;
  double part_margin_m = 0.01;              ///< the crop: the model's box at the hypothesis pose grown by this, ≥ 0
  std::size_t part_min_points = 50;         ///< least points of a crop, ≥ 3
  /// least q_h of a crop recognised on its own, in [0, 1]. A crop is more easily explained by a wrong model than a
  /// whole cluster (the mushroom's cap as the plate); a whole accepted with ≥ part_min_points outside its model's
  /// box whose crop fails this is not accepted.
  double part_min_q_h = 0.5;

  void validate() const {
    model.validate();
    match.validate();
    nbs::detail::require(surface_samples >= 100, "PpfRecogniserSetting.surface_samples must be >= 100, got ",
                         surface_samples);
    nbs::detail::require(validation_vertices >= 1, "PpfRecogniserSetting.validation_vertices must be >= 1, got ",
                         validation_vertices);
    nbs::detail::require_positive("PpfRecogniserSetting.normal_radius_m", normal_radius_m);
    nbs::detail::require_non_negative("PpfRecogniserSetting.tolerance_m", tolerance_m);
    nbs::detail::require(min_q_h >= 0.0 && min_q_h <= 1.0, "PpfRecogniserSetting.min_q_h must be in [0, 1], got ",
                         min_q_h);
    nbs::detail::require(min_v_h >= 0.0 && min_v_h <= 1.0, "PpfRecogniserSetting.min_v_h must be in [0, 1], got ",
                         min_v_h);
    nbs::detail::require_non_negative("PpfRecogniserSetting.ambiguity_margin", ambiguity_margin);
    nbs::detail::require_positive("PpfRecogniserSetting.ambiguity_distance", ambiguity_distance);
    nbs::detail::require_non_negative("PpfRecogniserSetting.part_margin_m", part_margin_m);
    nbs::detail::require(part_min_points >= 3, "PpfRecogniserSetting.part_min_points must be >= 3, got ",
                         part_min_points);
    nbs::detail::require(part_min_q_h >= 0.0 && part_min_q_h <= 1.0,
                         "PpfRecogniserSetting.part_min_q_h must be in [0, 1], got ", part_min_q_h);
  }
};

/// The thesis's recogniser (Sec. 3.4) over a ModelDatabase: per database model PPF voting on the cluster (normals
/// by estimate_scan_normals), every hypothesis verified by q_h (the model rendered with `Caster` into the cluster's
/// range image of `sensor`), the best refined by ICP (refine_pose) and rated again; the best model by q_h is
/// validated by v_h against `space` (borrowed; the caller integrates every scan into it). `learn` adds a model to the
/// database (mesh + feature table + metadata, ModelDatabase::add). Borrows the database and the space; keeps its
/// own copy of every model mesh for its casters (a caster may borrow the mesh it is built from).
template <RayCaster Caster, OccupancyProbability Space>
  requires std::constructible_from<Caster, const IndexedMesh&>
class PpfRecogniser {
public:
  PpfRecogniser(ModelDatabase& database, const AreaSensor& sensor, const Space& space,
                const PpfRecogniserSetting& setting = {})
      : db_(&database), sensor_(sensor), space_(&space), setting_(setting) {
    setting_.validate();
    sensor_.validate();
    for (const DatabaseModel& m : db_->models()) entries_.push_back(make_entry(m.mesh, m.metadata.name));
  }

  [[nodiscard]] const ModelDatabase& database() const { return *db_; }

  /// Thesis Sec. 3.4 on the whole cluster (see the class comment). Throws InvalidArgument for a non-empty cluster
  /// without a profile pose.
  [[nodiscard]] Recognition recognise(const scene::ObjectHypothesis&, const Scan& cluster) {
    return recognise_points(cluster, nullptr);
  }

  /// recognise(); if the cluster as a whole is accepted and at least part_min_points lie inside and outside the
  /// model's box at its pose (grown by part_margin_m; a neighbour touching a recognised object), that crop is
  /// recognised on its own: accepted as the same model with q_h ≥ part_min_q_h, it is the part; else the whole is
  /// not accepted (a wrong model fitting a piece) and the other models are tried as below. If the whole is neither
  /// accepted nor ambiguous: for the best hypothesis (after ICP) of each of the `part_models` best models by q_h,
  /// the crop to that model's box at that pose — if at least part_min_points and not all — is recognised on its
  /// own; the first crop accepted as that same model with q_h ≥ part_min_q_h is the part: a known object touching
  /// something else. Else the whole (also for an ambiguous whole: its pose, and so its box, is open).
  /// part_models = 0: recognise() and the whole.
  [[nodiscard]] PartRecognition recognise_part(const scene::ObjectHypothesis&, const Scan& cluster) {
    std::vector<ModelBest> per_model;
    PartRecognition out;
    out.recognition = recognise_points(cluster, &per_model);
    out.points.resize(cluster.size());
    std::iota(out.points.begin(), out.points.end(), std::size_t{0});
    if (setting_.part_models == 0 || out.recognition.ambiguous) return out;
    const auto big_enough = [&](std::size_t n) { return n >= setting_.part_min_points; };
    // A crop is the part when recognised on its own as the model that cropped it, with q_h ≥ part_min_q_h.
    const auto part_of = [&](std::size_t model, std::vector<std::size_t>& crop) {
      Recognition r = recognise_points(sub_scan(cluster, crop), nullptr);
      if (!r.accepted || r.q_h < setting_.part_min_q_h || r.model != entries_[model].name) return false;
      out.recognition = std::move(r);
      out.points = std::move(crop);
      return true;
    };
    std::optional<std::size_t> tried;  // the accepted whole's model, whose crop failed
    if (out.recognition.accepted) {
      // The recognised model is the first with the largest q_h (as recognise_points chose it), at the same pose.
      const ModelBest& best = *std::max_element(per_model.begin(), per_model.end(),
                                                [](const ModelBest& a, const ModelBest& b) { return a.q_h < b.q_h; });
      std::vector<std::size_t> crop = crop_to_model(cluster, entries_[best.model], out.recognition.pose);
      if (!big_enough(crop.size()) || !big_enough(cluster.size() - crop.size())) return out;
      // The model explains only a part: that part must be the model on its own too, else the whole's q_h came from
      // a wrong model fitting a piece (the mushroom's cap as the plate): not accepted; the other models' crops follow.
      if (part_of(best.model, crop)) return out;
      out.recognition.accepted = false;
      tried = best.model;
    }
    std::stable_sort(per_model.begin(), per_model.end(),
                     [](const ModelBest& a, const ModelBest& b) { return a.q_h > b.q_h; });
    if (tried)
      std::erase_if(per_model, [&](const ModelBest& m) { return m.model == *tried; });
    per_model.resize(std::min(per_model.size(), setting_.part_models));
    for (const ModelBest& m : per_model) {
      std::vector<std::size_t> crop = crop_to_model(cluster, entries_[m.model], m.pose);
      if (!big_enough(crop.size()) || crop.size() == cluster.size()) continue;
      if (part_of(m.model, crop)) return out;
    }
    return out;
  }

  /// Adds `mesh` (model frame) as `name` to the database (its PPF table built with setting.model) and to the
  /// recogniser. Throws InvalidArgument for an invalid name or mesh or a name already in the database, and what
  /// ModelDatabase::add throws (nothing changes then).
  void learn(const std::string& name, const IndexedMesh& mesh) {
    ModelDatabase::check_name(name);
    nbs::detail::require(db_->find(name) == nullptr, "PpfRecogniser::learn: a model named '", name,
                         "' is already in the database");
    Entry e = make_entry(mesh, name);
    db_->add(ModelMetadata{name, 0.0, {}, {"nbs_explore"}}, mesh, PpfModel(e.samples, setting_.model));
    entries_.push_back(std::move(e));
  }

private:
  struct Entry;

  /// The indices of the cluster's points inside the entry's box at `pose` (T_WM), grown by part_margin_m.
  [[nodiscard]] std::vector<std::size_t> crop_to_model(const Scan& cluster, const Entry& e, const Pose& pose) const {
    const Vec3 m = Vec3::Constant(setting_.part_margin_m);
    const Aabb grown{e.box.min - m, e.box.max + m};
    const Pose t_mw = pose.inverse();
    std::vector<std::size_t> crop;
    for (std::size_t i = 0; i < cluster.size(); ++i)
      if (grown.contains(t_mw * cluster.points[i])) crop.push_back(i);
    return crop;
  }

  /// The best hypothesis of one database model (entries_[model]) on a cluster, after ICP.
  struct ModelBest {
    std::size_t model = 0;
    Pose pose = Pose::Identity();
    double q_h = 0.0;
  };

  /// recognise() on `cluster`; each model's best hypothesis into *per_model if not null.
  [[nodiscard]] Recognition recognise_points(const Scan& cluster, std::vector<ModelBest>* per_model) {
    Recognition best;
    if (cluster.empty() || entries_.empty()) return best;
    nbs::detail::require(!cluster.profile_poses.empty(), "PpfRecogniser::recognise: the cluster has ",
                         cluster.size(), " points but no profile pose");
    const std::vector<Vec3> n = estimate_scan_normals(cluster, {.radius_m = setting_.normal_radius_m});
    OrientedPoints scene;
    for (std::size_t i = 0; i < cluster.size(); ++i)
      if (n[i].squaredNorm() > 0.0) scene.points.push_back(cluster.points[i]), scene.normals.push_back(n[i]);
    if (scene.size() < 3) return best;
    const RangeImage image = range_image(sensor_, cluster.profile_poses.front(), cluster.points);
    std::vector<std::pair<Pose, double>> best_rated;  // the best model's hypotheses with their q_h
    std::size_t best_k = 0;
    for (std::size_t k = 0; k < entries_.size(); ++k) {
      const Entry& e = entries_[k];
      const std::vector<PoseHypothesis> hyps = match_ppf(db_->models()[k].features, scene, setting_.match);
      std::vector<std::pair<Pose, double>> rated;
      double q_best = -1.0;
      Pose pose = Pose::Identity();
      for (const PoseHypothesis& h : hyps) {
        const double q = quality(e, h.pose, image);
        rated.emplace_back(h.pose, q);
        if (q > q_best) q_best = q, pose = h.pose;
      }
      if (q_best < 0.0) continue;
      const RefinedPose refined = refine_pose(e.samples, pose, cluster);
      const double q_refined = refined.icp.applied() ? quality(e, refined.pose, image) : -1.0;
      if (q_refined >= q_best) q_best = q_refined, pose = refined.pose;
      if (per_model) per_model->push_back({k, pose, q_best});
      if (q_best > best.q_h || best.model.empty()) {
        best.model = db_->models()[k].metadata.name;
        best.pose = pose;
        best.q_h = q_best;
        best_rated = std::move(rated);
        best_k = k;
      }
    }
    if (best.model.empty()) return best;
    const Entry& e = entries_[best_k];
    best.v_h = v_h(e, best.pose);
    best.accepted = best.q_h >= setting_.min_q_h && best.v_h >= setting_.min_v_h;
    if (best.accepted && setting_.reject_ambiguous) {
      // The best rated hypothesis that places the surface elsewhere, refined as the best was, and valid too.
      const double far = setting_.ambiguity_distance * e.box.extent().norm();
      std::stable_sort(best_rated.begin(), best_rated.end(),
                       [](const auto& a, const auto& b) { return a.second > b.second; });
      for (const auto& [pose, q] : best_rated) {
        if (e.metric->error(pose, best.pose).add_s_max_m < far) continue;
        Pose alt = pose;
        double q_alt = q;
        const RefinedPose refined = refine_pose(e.samples, pose, cluster);
        if (refined.icp.applied()) {
          const double q_refined = quality(e, refined.pose, image);
          if (q_refined >= q_alt && e.metric->error(refined.pose, best.pose).add_s_max_m >= far)
            q_alt = q_refined, alt = refined.pose;
        }
        best.q_h_alternative = q_alt;
        // The alternative must be acceptable itself (q_h and v_h bounds) and rate as well within the margin.
        if (q_alt >= setting_.min_q_h && q_alt >= best.q_h - setting_.ambiguity_margin &&
            v_h(e, alt) >= setting_.min_v_h) {
          best.ambiguous = true;
          best.accepted = false;
        }
        break;  // only the best other placement is tried
      }
    }
    return best;
  }

  struct Entry {
    std::string name;
    OrientedPoints samples;  ///< model frame
    Aabb box;
    std::unique_ptr<const IndexedMesh> mesh;  ///< owned copy: the caster may borrow it (the database's may move)
    std::unique_ptr<Caster> caster;           ///< built from *mesh
    /// ADD-S over the first validation_vertices samples (model frame); only with reject_ambiguous, else null
    std::unique_ptr<const SurfacePoseMetric> metric;
  };

  [[nodiscard]] Entry make_entry(const IndexedMesh& mesh, std::string name) const {
    mesh.validate();
    Entry e;
    e.name = std::move(name);
    e.samples = oriented_points(sample_surface(mesh, setting_.surface_samples, setting_.seed));
    for (const Vec3& v : mesh.vertices) e.box.extend(v);
    e.mesh = std::make_unique<const IndexedMesh>(mesh);
    e.caster = std::make_unique<Caster>(*e.mesh);
    if (setting_.reject_ambiguous) e.metric = std::make_unique<const SurfacePoseMetric>(validation_points(e));
    return e;
  }

  /// The first validation_vertices samples of the model (model frame): the vertices of v_h and of the ADD-S metric.
  [[nodiscard]] std::span<const Vec3> validation_points(const Entry& e) const {
    return {e.samples.points.data(), std::min(setting_.validation_vertices, e.samples.size())};
  }

  [[nodiscard]] double v_h(const Entry& e, const Pose& pose) const {
    return validate_hypothesis(*space_, validation_points(e), pose).v_h();
  }

  [[nodiscard]] double quality(const Entry& e, const Pose& pose, const RangeImage& image) const {
    return verify_hypothesis(*e.caster, e.box, pose, image, setting_.tolerance_m, setting_.threads).q_h();
  }

  ModelDatabase* db_;
  AreaSensor sensor_;
  const Space* space_;
  PpfRecogniserSetting setting_;
  std::vector<Entry> entries_;
};

}  // namespace nbs::explore
