// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Recognition of the clusters of one overview frame (the scene-exploration loop, scene_exploration.hpp): what a
/// recogniser reports per cluster (`Recognition`), the `ObjectRecogniser` concept, and `recognise_clusters`, which
/// also splits a cluster that holds a known object and a neighbour (objects that touch fall into one Euclidean
/// cluster; thesis Sec. 3.4 assumes one object per cluster) when the recogniser can recognise a part of a cluster
/// (`PartRecogniser`). World frame, metres.

#include <algorithm>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/core/scan.hpp"
#include "nbs/mesh/indexed_mesh.hpp"
#include "nbs/scene/segmentation.hpp"

namespace nbs::explore {

/// The outcome of recognising one cluster: the best hypothesis over all database models (by q_h after ICP).
struct Recognition {
  std::string model;               ///< database name; empty if no model gave a hypothesis
  Pose pose = Pose::Identity();    ///< T_WM (model frame → world)
  double q_h = 0.0;                ///< Eq. 3.10, in [0, 1]
  double v_h = 0.0;                ///< Eq. 3.11, in [0, 1]
  /// q_h ≥ the recogniser's bound and v_h ≥ its bound (thesis: 0.66), not ambiguous (a recogniser may refuse more:
  /// PpfRecogniser::recognise_part a whole whose crop to the model's box is not the model on its own)
  bool accepted = false;
  /// The data fit another placement of the same model as well (PpfRecogniserSetting::reject_ambiguous): a
  /// hypothesis that puts some of the surface elsewhere (largest nearest distance, ADD-S max, ≥ ambiguity_distance ×
  /// the model's diagonal) is valid too and rates q_h ≥ q_h − ambiguity_margin. The model is likely right; its pose
  /// is not determined by this view (a part that tells the poses apart is hidden).
  bool ambiguous = false;
  double q_h_alternative = 0.0;    ///< q_h of the other placement tried (0 if none was tried)
};

/// A recognition of a cluster or of a part of it: `points` are the ascending indices into the cluster's points the
/// recognition is about — all of them, or (accepted or ambiguous only) a proper subset: the object recognised there,
/// the rest of the cluster being something else.
struct PartRecognition {
  Recognition recognition;
  std::vector<std::size_t> points;
};

/// Recognition against a growing database: `recognise(hypothesis, cluster)` with the cluster's points as a Scan of
/// one frame (the frame's pose); `learn(name, mesh)` adds a model (model frame) to the database.
template <class R>
concept ObjectRecogniser = requires(R& r, const scene::ObjectHypothesis& h, const Scan& cluster, const std::string& name,
                                    const IndexedMesh& mesh) {
  { r.recognise(h, cluster) } -> std::same_as<Recognition>;
  r.learn(name, mesh);
};

/// A recogniser that can also find a known object in part of a cluster: `recognise_part(hypothesis, cluster)`
/// (see PartRecognition) — a known object touching something else, recognised or not as a whole.
template <class R>
concept PartRecogniser = ObjectRecogniser<R> && requires(R& r, const scene::ObjectHypothesis& h, const Scan& cluster) {
  { r.recognise_part(h, cluster) } -> std::same_as<PartRecognition>;
};

/// What the loop concluded about a cluster in a step.
enum class ClusterState : std::uint8_t {
  recognised,   ///< a database model was accepted
  modeling,     ///< modeled in this step
  unexplained,  ///< not recognised, not modeled (yet)
  /// not recognised, or ambiguous, but its centroid lies in the box of an object the loop modeled before, or it is
  /// a split piece of a cluster where such an object was recognised (not modeled again; only the loop gives it)
  modeled,
  ambiguous,    ///< a database model fits, but the view leaves its pose open (Recognition::ambiguous); not modeled
};

[[nodiscard]] inline const char* to_string(ClusterState s) {
  switch (s) {
    case ClusterState::recognised: return "recognised";
    case ClusterState::modeling: return "modeling";
    case ClusterState::unexplained: return "unexplained";
    case ClusterState::modeled: return "modeled";
    case ClusterState::ambiguous: return "ambiguous";
  }
  return "?";
}

struct ClusterRecord {
  Aabb box;                        ///< the hypothesis box (the unknown area for modeling)
  Vec3 centroid = Vec3::Zero();
  std::size_t points = 0;
  Recognition recognition;
  ClusterState state = ClusterState::unexplained;
  /// The segmentation cluster it comes from (index into the step's Segmentation::objects): records that share it
  /// are the pieces of one cluster that held several objects.
  int segment = 0;
  bool split = false;  ///< a piece of a cluster that held a recognised object and more (recognise_clusters)
  /// recognised from an earlier step (explore_scene, ExplorationSetting::remember_recognitions): this view left the
  /// pose ambiguous (`recognition.ambiguous`, not `accepted`; q_h / v_h this view's), `recognition.pose` is the
  /// placement accepted unambiguously before, and the state is `recognised`
  bool remembered = false;
  std::vector<std::size_t> indices;  ///< its points: indices into the step's overview frame, ascending
};

/// A cluster's record with its hypothesis (indices into the frame; its box is the unknown area for modeling).
struct RecognisedCluster {
  ClusterRecord record;
  scene::ObjectHypothesis hypothesis;
};

/// The points of `frame` with the given indices, as a Scan of the frame's first pose (the frame has one).
[[nodiscard]] inline Scan sub_scan(const Scan& frame, std::span<const std::size_t> indices) {
  detail::require(!frame.profile_poses.empty(), "sub_scan: the frame has no profile pose");
  Scan out;
  out.profile_poses = {frame.profile_poses.front()};
  for (const std::size_t i : indices) {
    detail::require(i < frame.size(), "sub_scan: index ", i, " is outside the frame of ", frame.size(), " points");
    out.add_point(frame.points[i], 0);
  }
  return out;
}

/// Recognises every cluster of `seg` (segmented from `frame` with `s`), in segmentation order; the state is
/// recognised, ambiguous or unexplained. With a PartRecogniser and max_parts > 0, a cluster is recognised with
/// recognise_part: when it returns a part (a known object in part of the cluster), that part becomes a record of its own, and the
/// rest of the cluster, clustered again (scene::split_hypothesis), is recognised the same way — up to max_parts
/// splits per segmentation cluster, then plain recognise. Such records have `split` set; every record names its
/// `segment`. Throws InvalidArgument for max_parts < 0, a segmentation without a plane, or a recogniser's part that
/// is empty, unsorted, out of range, or not recognised (neither accepted nor ambiguous).
template <ObjectRecogniser R>
[[nodiscard]] std::vector<RecognisedCluster> recognise_clusters(R& recogniser, const Scan& frame,
                                                                const scene::Segmentation& seg,
                                                                const scene::SegmentationSettings& s, int max_parts) {
  detail::require(max_parts >= 0, "recognise_clusters: max_parts must be >= 0, got ", max_parts);
  detail::require(seg.status == scene::SegmentationStatus::ok, "recognise_clusters: the segmentation has no plane");
  std::vector<RecognisedCluster> out;
  const auto record = [&](scene::ObjectHypothesis h, Recognition r, std::size_t segment, bool split) {
    RecognisedCluster c;
    c.record.box = h.box;
    c.record.centroid = h.centroid;
    c.record.points = h.points.size();
    c.record.state = r.accepted    ? ClusterState::recognised
                     : r.ambiguous ? ClusterState::ambiguous
                                   : ClusterState::unexplained;
    c.record.recognition = std::move(r);
    c.record.segment = static_cast<int>(segment);
    c.record.split = split;
    c.record.indices = h.indices;
    c.hypothesis = std::move(h);
    out.push_back(std::move(c));
  };
  for (std::size_t k = 0; k < seg.objects.size(); ++k) {
    std::vector<scene::ObjectHypothesis> work{seg.objects[k]};  // a stack: the rest of a split, in order
    int parts = 0;
    while (!work.empty()) {
      scene::ObjectHypothesis h = std::move(work.back());
      work.pop_back();
      const Scan cluster = sub_scan(frame, h.indices);
      if constexpr (PartRecogniser<R>) {
        if (parts < max_parts) {
          PartRecognition p = recogniser.recognise_part(h, cluster);
          const std::size_t n = h.points.size();
          detail::require(!p.points.empty() && std::is_sorted(p.points.begin(), p.points.end()) &&
                              std::adjacent_find(p.points.begin(), p.points.end()) == p.points.end() &&
                              p.points.back() < n,
                          "recognise_clusters: the recogniser's part of a cluster of ", n,
                          " points is empty, unsorted or out of range");
          if (p.points.size() == n) {
            record(std::move(h), std::move(p.recognition), k, parts > 0);
            continue;
          }
          detail::require(p.recognition.accepted || p.recognition.ambiguous,
                          "recognise_clusters: the recogniser returned a part of a cluster it did not recognise");
          ++parts;
          std::vector<char> in_part(n, 0);
          std::vector<std::size_t> members;
          for (const std::size_t i : p.points) in_part[i] = 1, members.push_back(h.indices[i]);
          std::vector<scene::ObjectHypothesis> rest =
              scene::split_hypothesis(frame.points, h, [&](std::size_t i) { return in_part[i] == 0; }, seg.plane.plane, s);
          record(scene::make_hypothesis(frame.points, members, seg.plane.plane, s), std::move(p.recognition), k, true);
          for (auto it = rest.rbegin(); it != rest.rend(); ++it) work.push_back(std::move(*it));
          continue;
        }
      }
      Recognition r = recogniser.recognise(h, cluster);
      record(std::move(h), std::move(r), k, parts > 0);
    }
  }
  return out;
}

}  // namespace nbs::explore
